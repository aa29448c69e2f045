"""A range-scan-like test surface made from scratch (no source data), and curves on it that are
hard for constrained refinement; the same mesh as holey_mesh() in
tests/solvers/recipes/conforming_test.cpp (same generator, same seeds).

holey_scan(n, holes, seed, sliver): a bumpy n×n grid on the unit square (z = 0.08 sin(3x + 1)
cos(4y)), interior vertices jittered by up to 0.3 h, with `holes` small round holes (radius
0.8–1.8 h; faces whose centroid is inside are removed, unused vertices dropped). `sliver`: odd
rows moved up by 0.45 h (every other row of triangles is a sliver).
hard_curves(V): (vertices, values) of four curves with data in [0, 1]: a path with a sharp bend,
a path leaving its first vertex at a small angle to it, one near the top, one with values
varying along it.

Imported by tests/cli/test_cli_curves.py and python/tests/test_curves.py; run as
`python3 make_holey_scan.py OUT` it writes OUT.obj and OUT.txt (a curves file).
"""
import math
import sys

_MASK = (1 << 64) - 1


class _Lcg:
    def __init__(self, seed):
        self.s = seed & _MASK

    def next(self):
        self.s = (self.s * 6364136223846793005 + 1442695040888963407) & _MASK
        return (self.s >> 11) * 2.0 ** -53


def holey_scan(n=40, holes=25, seed=4, sliver=False):
    rng = _Lcg(seed)
    h = 1.0 / n
    P = []
    for j in range(n + 1):
        for i in range(n + 1):
            x, y = i * h, j * h
            if 0 < i < n and 0 < j < n:
                x += (rng.next() - 0.5) * 0.6 * h
                y += (0.45 * h if j % 2 else 0.0) if sliver else (rng.next() - 0.5) * 0.6 * h
            P.append((x, y, 0.08 * math.sin(3 * x + 1) * math.cos(4 * y)))
    hs = []
    for _ in range(holes):
        x = 0.1 + 0.8 * rng.next()
        y = 0.1 + 0.8 * rng.next()
        hs.append((x, y, (0.8 + rng.next()) * h))
    faces = []

    def add(a, b, c):
        mx = (P[a][0] + P[b][0] + P[c][0]) / 3.0
        my = (P[a][1] + P[b][1] + P[c][1]) / 3.0
        if any((mx - x) * (mx - x) + (my - y) * (my - y) < r * r for x, y, r in hs):
            return
        faces.append((a, b, c))

    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            if (i + j) % 2:
                add(a, b, c)
                add(a, c, d)
            else:
                add(a, b, d)
                add(b, c, d)
    ids = {}
    for f in faces:
        for v in f:
            ids.setdefault(v, len(ids))
    V = [None] * len(ids)
    for v, k in ids.items():
        V[k] = P[v]
    F = [tuple(ids[v] for v in f) for f in faces]
    return V, F


def nearest(V, x, y):
    best, d = 0, float("inf")
    for k, p in enumerate(V):
        e = math.hypot(p[0] - x, p[1] - y)
        if e < d:
            best, d = k, e
    return best


def hard_curves(V):
    def at(x, y):
        return nearest(V, x, y)
    return [([at(0.1, 0.1), at(0.9, 0.5), at(0.25, 0.5)], [0.0]),
            ([at(0.1, 0.1), at(0.9, 0.7)], [0.5]),
            ([at(0.1, 0.9), at(0.9, 0.85)], [1.0]),
            ([at(0.3, 0.95), at(0.62, 0.2)], [0.0, 1.0])]


def curves_text(curves):
    lines = []
    for vertices, values in curves:
        vals = " ".join(repr(float(x)) for x in values)
        ids = " ".join(str(v) for v in vertices)
        lines.append(f"{vals} {ids}" if len(values) == 1 else f"{vals} : {ids}")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    V, F = holey_scan()
    with open(sys.argv[1] + ".obj", "w") as f:
        for p in V:
            f.write("v %.17g %.17g %.17g\n" % p)
        for t in F:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))
    with open(sys.argv[1] + ".txt", "w") as f:
        f.write(curves_text(hard_curves(V)))
