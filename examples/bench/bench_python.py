#!/usr/bin/env python3
"""Benchmark of the Python package: what the binding adds to the C++ library's own time.

For each mesh, the median over --repeat runs of
  - ifem.laplacian(V, F): the whole Python call, and info["seconds"], the C++ library's own time
    (prepare the intrinsic Delaunay triangulation + assemble L and M); the difference is the
    binding's overhead (checking and converting V and F, building the scipy matrices);
  - a heat-distance query, HeatDistanceSolver.compute_distance(source): the whole Python call
    and the solver's own query time (solver.last_query_seconds).
  - the tufted-cover Laplacian (path="tufted", what robust-laplacian's mesh_laplacian computes)
    and point_cloud_laplacian(P, k=30) on the jittered vertices of icosphere(224) (501,762
    points), for the side-by-side table with geometry-central's figures in BENCHMARKS.md.
Meshes: icosphere(23 / 71 / 224) (10k / 100k / 1M faces) as written by `ifem_bench foundation`
to /tmp/ifem_bench_foundation (bumpy grids of the same sizes when absent), and, when
../shared/data is present, rocketship (56k faces) and igea (269k faces).

  build/examples/ifem_bench foundation --repeat 1     # writes the icosphere OBJs once
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


ICOSPHERES = pathlib.Path("/tmp/ifem_bench_foundation")


def meshes(max_faces):
    for n, f in ((23, 10_580), (71, 100_820), (224, 1_003_520)):
        if f > max_faces:
            continue
        obj = ICOSPHERES / f"icosphere_{n}.obj"
        if obj.exists():
            yield f"icosphere({n})", *ifem.read_mesh(obj)
        else:
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
        def tufted():
            return ifem.laplacian(V, F, path="tufted", return_info=True)[2]["seconds"]
        total, own = median_time(tufted, args.repeat)
        print(f"{name:<16}{len(F):>9}  {total:>8.4f}s{own:>8.4f}s{100 * (total - own) / own:>9.1f}%"
              "  laplacian(V, F, path='tufted')")
        if hasattr(ifem, "HeatDistanceSolver"):
            solver = ifem.HeatDistanceSolver(V, F)
            if hasattr(solver, "last_query_seconds"):
                def query():
                    solver.compute_distance(0)
                    return solver.last_query_seconds
                total, own = median_time(query, args.repeat)
                print(f"{name:<16}{len(F):>9}  {total:>8.4f}s{own:>8.4f}s"
                      f"{100 * (total - own) / own:>9.1f}%  HeatDistanceSolver.compute_distance")
    if args.max_faces >= 1_000_000:
        point_cloud_rows(args.repeat)


def point_cloud_rows(repeat):
    obj = ICOSPHERES / "icosphere_224.obj"
    if not obj.exists():
        return
    V, _ = ifem.read_mesh(obj)
    rng = np.random.default_rng(1)
    h = 2.0 * np.pi / (5 * 224)  # about the icosphere's edge length on the unit sphere
    P = V + 0.1 * h * rng.standard_normal(V.shape)

    def cloud():
        return ifem.point_cloud_laplacian(P, k=30, return_info=True)[2]["seconds"]
    total, own = median_time(cloud, repeat)
    print(f"{'jittered points':<16}{len(P):>9}  {total:>8.4f}s{own:>8.4f}s"
          f"{100 * (total - own) / own:>9.1f}%  point_cloud_laplacian(P, k=30)")


if __name__ == "__main__":
    main()
