"""Writes soup_icosphere.obj (tests/data/PROVENANCE.md): a triangle soup made from scratch, no
source data. The unit icosphere (icosahedron, two 1-to-4 subdivisions: 162 vertices, 320
near-equilateral faces) cut into 8 pieces by the octant of each face's centroid, every piece with
its own copies of its vertices (so pieces meet at coincident vertices, not shared ones); then a
lone triangle off the sphere (a one-face piece) and a zero-area face whose three corners coincide
(a flat piece: no tangent plane). 10 connected components, 9 with area.
Run: python3 tests/data/make_soup.py tests/data/soup_icosphere.obj"""
import sys

import numpy as np


def icosphere(levels):
    t = (1 + 5 ** 0.5) / 2
    V = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t],
         [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]]
    F = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
         [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
         [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(levels):
        mid, G = {}, []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = V[a] + V[b]
                V.append(p / np.linalg.norm(p))
                mid[k] = len(V) - 1
            return mid[k]

        for a, b, c in F:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            G += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        F = G
    return np.array(V), np.array(F)


def main(path):
    V, F = icosphere(2)
    octant = ((V[F].mean(axis=1) > 0) * [1, 2, 4]).sum(axis=1)
    out_v, out_f = [], []
    for k in range(8):
        faces = F[octant == k]
        used = np.unique(faces)
        new = {int(u): len(out_v) + i for i, u in enumerate(used)}
        out_v += [V[u] for u in used]
        out_f += [[new[int(a)] for a in f] for f in faces]
    n = len(out_v)
    out_v += [np.array([2.0, 0.0, 0.0]), np.array([2.3, 0.0, 0.0]), np.array([2.0, 0.3, 0.0])]
    out_f.append([n, n + 1, n + 2])
    out_v += [np.array([0.0, 0.0, 2.0])] * 3
    out_f.append([n + 3, n + 4, n + 5])
    with open(path, "w") as f:
        f.write("# triangle soup: tests/data/make_soup.py (PROVENANCE.md)\n")
        for p in out_v:
            f.write("v %.17g %.17g %.17g\n" % tuple(p))
        for t in out_f:
            f.write("f %d %d %d\n" % tuple(np.array(t) + 1))


if __name__ == "__main__":
    main(sys.argv[1])
