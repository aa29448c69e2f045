"""`ifem isolines` and the --isolines option of `ifem distance` / `ifem poisson`: every point on
the level (checked through its surface point and its position), loops closed where the topology
says so, open curves ending on the boundary, both file formats, and every refusal (exit code, one
stderr line, no partial output). Also `ifem distance --no-path-bounds` (issue 30)."""

import math

from clitools import SPOT_VERTICES, close, lines, obj_vertices, write_obj


def uv_sphere(n_lat, n_lon):
    """Unit sphere: poles 0 and 1, rings between (positions, 1-based faces)."""
    v = [(0.0, 0.0, 1.0), (0.0, 0.0, -1.0)]
    for i in range(1, n_lat):
        th = math.pi * i / n_lat
        for j in range(n_lon):
            ph = 2 * math.pi * j / n_lon + 0.37 * i  # twisted rings: no symmetric ties
            v.append((math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)))

    def ring(i, j):
        return 3 + (i - 1) * n_lon + j % n_lon

    f = []
    for j in range(n_lon):
        f.append((1, ring(1, j), ring(1, j + 1)))
        f.append((2, ring(n_lat - 1, j + 1), ring(n_lat - 1, j)))
        for i in range(1, n_lat - 1):
            a, b, c, d = ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)
            f += [(a, b, c), (a, c, d)]
    return v, f


def grid(n, jitter=0.0):
    """[0, 1]² in n×n cells, alternating diagonals; interior vertices moved by jitter·h."""
    v = []
    for j in range(n + 1):
        for i in range(n + 1):
            dx = dy = 0.0
            if 0 < i < n and 0 < j < n and jitter:
                dx = jitter / n * math.sin(12.9898 * i + 78.233 * j)
                dy = jitter / n * math.cos(39.346 * i + 11.135 * j)
            v.append((i / n + dx, j / n + dy, 0.0))
    f = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i + 1, j * (n + 1) + i + 2
            c, d = b + n + 1, a + n + 1
            f += [(a, b, c), (a, c, d)] if (i + j) % 2 else [(a, b, d), (b, c, d)]
    return v, f


def write_values(path, values):
    path.write_text("".join(f"{x:.17g}\n" for x in values))


def obj_lines(path):
    """The 'l' lines of an OBJ: (0-based ids, closed) per polyline."""
    out = []
    for t in lines(path):
        if t.startswith("l "):
            ids = [int(x) - 1 for x in t.split()[1:]]
            closed = len(ids) > 2 and ids[0] == ids[-1]
            out.append((ids[:-1] if closed else ids, closed))
    return out


def surface_points(path):
    """--points: (isoline, value, face, (b0, b1, b2), (x, y, z)) per line."""
    out = []
    for t in lines(path):
        if t.startswith("#"):
            continue
        x = t.split()
        out.append((int(x[0]), float(x[1]), int(x[2]), tuple(map(float, x[3:6])),
                    tuple(map(float, x[6:9]))))
    return out


# a height field on a sphere: one closed loop per level; every point's surface point and
# position give the level to 1e-12 (z is linear, so the interpolated field is the position's z)
def test_isolines_sphere_height(cli):
    v, f = uv_sphere(16, 24)
    write_obj(cli.out / "s.obj", v, f)
    write_values(cli.out / "z.txt", [p[2] for p in v])
    levels = [-0.83, -0.2, 0.0, 0.45, 0.9]
    r = cli.ok("isolines", "s.obj", "z.txt", "--values", ",".join(map(str, levels)), "-o",
               "iso.obj", "--points", "p.txt", "--quiet")
    assert "wrote iso.obj: 5 isolines (5 closed) at 5 levels" in r.out, r.out
    pieces = obj_lines(cli.out / "iso.obj")
    pts = obj_vertices(cli.out / "iso.obj")
    assert len(pieces) == 5 and all(closed for _, closed in pieces)
    for k, (ids, _) in enumerate(pieces):
        assert all(abs(pts[i][2] - levels[k]) < 1e-12 for i in ids)
    sp = surface_points(cli.out / "p.txt")
    assert len(sp) == len(pts)
    for (line, value, face, b, x), p in zip(sp, pts):
        assert value == levels[line]
        corners = [v[i - 1] for i in f[face]]
        z = sum(bk * c[2] for bk, c in zip(b, corners))
        assert abs(z - value) < 1e-12 and min(b) >= 0 and abs(sum(b) - 1) < 1e-15
        assert x == p
    # the same as a PLY line set: a loop's first point repeated, one edge per segment
    cli.ok("isolines", "s.obj", "z.txt", "--values", ",".join(map(str, levels)), "-o",
           "iso.ply", "--quiet")
    text = lines(cli.out / "iso.ply")
    n_pts = sum(len(ids) for ids, _ in pieces)
    assert f"element vertex {n_pts + 5}" in text and f"element edge {n_pts}" in text


# distance from a pole of a sphere: each level one closed loop (--isolines of ifem distance),
# and ifem isolines on the distance's PLY gives the same file
def test_distance_isolines_on_sphere(cli):
    v, f = uv_sphere(20, 30)
    write_obj(cli.out / "s.obj", v, f)
    r = cli.ok("distance", "s.obj", "--source", "0", "--isolines", "4", "--isolines-out",
               "iso.obj", "-o", "d.ply", "--quiet")
    assert "wrote iso.obj: 4 isolines (4 closed) at 4 levels" in r.out, r.out
    cli.ok("isolines", "s.obj", "d.ply", "--property", "distance", "--count", "4", "-o",
           "iso2.obj", "--quiet")
    assert lines(cli.out / "iso.obj")[1:] == lines(cli.out / "iso2.obj")[1:]
    # levels evenly inside [0, max d]: the loops sit near z = cos(level) (heat error ≪ 0.1)
    pieces = obj_lines(cli.out / "iso.obj")
    pts = obj_vertices(cli.out / "iso.obj")
    zs = [sum(pts[i][2] for i in ids) / len(ids) for ids, _ in pieces]
    assert zs == sorted(zs, reverse=True)
    assert all(abs(z - math.cos(math.pi * (k + 1) / 5)) < 0.1 for k, z in enumerate(zs)), zs


# an open domain: each isoline of a linear field is one open straight curve from boundary to
# boundary; poisson's --isolines of u = x (held at x = 0 and x = 1) gives three open curves
def test_isolines_open_curves_end_on_boundary(cli):
    v, f = grid(10, jitter=0.3)
    write_obj(cli.out / "g.obj", v, f)
    write_values(cli.out / "f.txt", [p[0] + 0.3 * p[1] for p in v])
    cli.ok("isolines", "g.obj", "f.txt", "--count", "3", "-o", "iso.obj", "--quiet")
    pieces = obj_lines(cli.out / "iso.obj")
    pts = obj_vertices(cli.out / "iso.obj")
    assert len(pieces) == 3

    def on_boundary(p):
        return min(p[0], 1 - p[0], p[1], 1 - p[1]) < 1e-12

    for k, (ids, closed) in enumerate(pieces):
        assert not closed
        assert on_boundary(pts[ids[0]]) and on_boundary(pts[ids[-1]])
        assert not any(on_boundary(pts[i]) for i in ids[1:-1])
        assert all(abs(pts[i][0] + 0.3 * pts[i][1] - 1.3 * (k + 1) / 4) < 1e-12 for i in ids)
    sides = [i for i, p in enumerate(v) if p[0] in (0.0, 1.0)]
    (cli.out / "bc.txt").write_text("".join(f"{i} {v[i][0]}\n" for i in sides))
    r = cli.ok("poisson", "g.obj", "--dirichlet", "bc.txt", "--isolines", "3",
               "--isolines-out", "u.ply", "-o", "u.txt", "--quiet")
    assert "wrote u.ply: 3 isolines (0 closed) at 3 levels" in r.out, r.out


def test_isolines_bad_input(cli):
    cli.ok("distance", cli.spot, "--source", "0", "-o", "d.ply", "--quiet")
    out = cli.out / "iso.obj"
    cli.fails_no_partial(r"value 9 is outside the field's range \[0, 1\.58", out, "isolines",
                         cli.spot, "d.ply", "--values", "0.5,9", "-o", out, rc=1)
    cli.fails_no_partial(r"no per-vertex property 'u' \(it has: distance\)", out, "isolines",
                         cli.spot, "d.ply", "--property", "u", "--count", "2", "-o", out, rc=1)
    write_values(cli.out / "short.txt", [0.0, 1.0, 2.0])
    cli.fails_no_partial(rf"short.txt: 3 values, the mesh has {SPOT_VERTICES} vertices", out,
                         "isolines", cli.spot, "short.txt", "--count", "2", "-o", out, rc=1)
    cli.fails_no_partial(r"exactly one of --values", out, "isolines", cli.spot, "d.ply",
                         "--count", "2", "--values", "0.1", "-o", out, rc=2)
    cli.fails_no_partial(r"'x' is not a finite number", out, "isolines", cli.spot, "d.ply",
                         "--values", "0.1,x", "-o", out, rc=2)
    cli.fails_no_partial(r"--isolines N and --isolines-out FILE go together", out, "distance",
                         cli.spot, "--source", "0", "--isolines", "3", "-o",
                         out.with_suffix(".ply"), rc=2)
    (cli.out / "one.txt").write_text("0\n")
    cli.fails_no_partial(r"--isolines: one field only", out, "distance", cli.spot,
                         "--sources-batch", "one.txt", "--isolines", "3", "--isolines-out", out,
                         "-o", "d.npy", rc=2)
    (cli.out / "pts.xyz").write_text("0 0 0\n1 0 0\n0 1 0\n1 1 1\n")
    write_values(cli.out / "four.txt", [0.0, 1.0, 2.0, 3.0])
    cli.fails_no_partial(r"need a mesh with faces", out, "isolines", "pts.xyz", "four.txt",
                         "--count", "1", "-o", out, rc=1)


# --no-path-bounds: the heat method's raw values. On a flat domain the exact distance is the
# straight line, so the clamp can only move values towards it: never a larger error, and here
# it moves some
def test_distance_no_path_bounds(cli):
    v, f = grid(16, jitter=0.35)
    write_obj(cli.out / "g.obj", v, f)
    cli.ok("distance", "g.obj", "--source", "0", "-o", "on.txt", "--quiet")
    cli.ok("distance", "g.obj", "--source", "0", "--no-path-bounds", "-o", "off.txt", "--quiet")
    on = [float(x) for x in lines(cli.out / "on.txt")]
    off = [float(x) for x in lines(cli.out / "off.txt")]
    exact = [math.hypot(p[0], p[1]) for p in v]
    assert all(abs(a - e) <= abs(b - e) + 1e-12 for a, b, e in zip(on, off, exact))
    moved = sum(not close(a, b, 1e-9) for a, b in zip(on, off))
    assert moved > 10, moved
    assert all(a >= e - 1e-12 for a, e in zip(on, exact))  # the chord lower bound holds
    assert any(b < e - 1e-4 for b, e in zip(off, exact))  # which the raw values break
