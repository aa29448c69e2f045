#!/usr/bin/env python3
"""Median relative error of a distance file against the great-circle distance on the unit sphere.

    python3 scripts/sphere_distance_error.py ico.ply d.txt [SOURCE]

ico.ply: a binary little-endian PLY of a sphere mesh centred at the origin, e.g. from
`ifem_multigrid_measure N write ico.ply` (its vertices are projected onto the unit sphere here);
d.txt: `ifem distance ico.ply --source SOURCE -o d.txt` (one value per vertex). Prints the median
of |d - arc| / arc over every vertex but the source, and the largest |d - arc| (the figures of
docs/decisions.md D-316 and D-355). Needs numpy.
"""
import sys

import numpy as np


def read_ply_positions(path):
    types = {"float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8"}
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            sys.exit(f"{path}: not a PLY file")
        n, props, element = None, [], None
        while True:
            line = f.readline().decode().strip()
            if line.startswith("format") and "binary_little_endian" not in line:
                sys.exit(f"{path}: only binary little-endian PLY is read here")
            if line.startswith("element"):
                element = line.split()[1]
                if element == "vertex":
                    n = int(line.split()[2])
            elif line.startswith("property") and element == "vertex":
                props.append(line.split()[1])
            elif line == "end_header":
                break
        dtype = np.dtype([(f"p{i}", types[p]) for i, p in enumerate(props)])
        v = np.frombuffer(f.read(n * dtype.itemsize), dtype=dtype, count=n)
    return np.stack([v["p0"], v["p1"], v["p2"]], axis=1).astype(float)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    p = read_ply_positions(sys.argv[1])
    p /= np.linalg.norm(p, axis=1)[:, None]
    d = np.loadtxt(sys.argv[2])
    src = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    if d.shape != (p.shape[0],):
        sys.exit(f"{sys.argv[2]}: {d.size} values for {p.shape[0]} vertices")
    arc = np.arccos(np.clip(p @ p[src], -1.0, 1.0))
    keep = np.arange(p.shape[0]) != src
    rel = np.abs(d[keep] - arc[keep]) / arc[keep]
    print(f"median relative error {100 * np.median(rel):.4f} %, largest |d - arc| "
          f"{np.max(np.abs(d - arc)):.6f}")


if __name__ == "__main__":
    main()
