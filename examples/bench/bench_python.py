#!/usr/bin/env python3
"""Benchmark of the Python package: what the binding adds to the C++ library's own time.

For each mesh, the median over --repeat runs of
  - ifem.laplacian(V, F): the whole Python call, and info["seconds"], the C++ library's own time
    (prepare the intrinsic Delaunay triangulation + assemble L and M); the difference is the
    binding's overhead (checking and converting V and F, building the scipy matrices);
  - a heat-distance query, HeatDistanceSolver.compute_distance(source): the whole Python call
    and the solver's own query time (solver.last_query_seconds).
Meshes: bumpy grids generated here at 10k, 100k and 1M faces, and, when ../shared/data is
present, rocketship (56k faces) and igea (269k faces).

  PYTHONPATH=build/python /usr/bin/python3 examples/bench/bench_python.py --repeat 5
"""

import argparse
import os
import pathlib
import statistics
import time

import numpy as np

import ifem

SHARED = pathlib.Path(__file__).resolve().parents[2].parent / "shared" / "data" / "meshes"


def bumpy_grid(faces):
    n = int(round((faces / 2) ** 0.5)) + 1
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    V = np.c_[x.ravel(), y.ravel(), 0.05 * np.sin(9 * x.ravel()) * np.cos(7 * y.ravel())]
    a = (np.arange(n - 1)[None, :] + n * np.arange(n - 1)[:, None]).ravel()
    F = np.r_[np.c_[a, a + 1, a + n + 1], np.c_[a, a + n + 1, a + n]].astype(np.int32)
    return V, F


def meshes(max_faces):
    for f in (10_000, 100_000, 1_000_000):
        if f <= max_faces:
            yield f"grid {f // 1000}k", *bumpy_grid(f)
    for name in ("rocketship.ply", "igea_268k.ply"):
        p = SHARED / name
        if p.exists():
            V, F = ifem.read_mesh(p)
            if len(F) <= max_faces:
                yield name, V, F


def median_time(fn, repeat):
    totals, inner = [], []
    for _ in range(repeat):
        t = time.perf_counter()
        own = fn()
        totals.append(time.perf_counter() - t)
        inner.append(own)
    return statistics.median(totals), statistics.median(inner)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--max-faces", type=int, default=2_000_000)
    args = ap.parse_args()
    print(f"ifem {ifem.__version__}, numpy {np.__version__}, OMP_NUM_THREADS="
          f"{os.environ.get('OMP_NUM_THREADS', 'unset')}, median of {args.repeat}")
    print(f"{'mesh':<16}{'faces':>9}  {'call':>9}{'C++':>9}{'overhead':>10}  what")
    for name, V, F in meshes(args.max_faces):
        def lap():
            return ifem.laplacian(V, F, return_info=True)[2]["seconds"]
        total, own = median_time(lap, args.repeat)
        print(f"{name:<16}{len(F):>9}  {total:>8.4f}s{own:>8.4f}s{100 * (total - own) / own:>9.1f}%"
              "  laplacian(V, F) -> L, M")
        if hasattr(ifem, "HeatDistanceSolver"):
            solver = ifem.HeatDistanceSolver(V, F)
            if hasattr(solver, "last_query_seconds"):
                def query():
                    solver.compute_distance(0)
                    return solver.last_query_seconds
                total, own = median_time(query, args.repeat)
                print(f"{name:<16}{len(F):>9}  {total:>8.4f}s{own:>8.4f}s"
                      f"{100 * (total - own) / own:>9.1f}%  HeatDistanceSolver.compute_distance")


if __name__ == "__main__":
    main()
