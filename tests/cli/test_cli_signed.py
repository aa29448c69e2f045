"""`ifem distance --signed`: signed distance to a circle (closed, and with 20 % of its arc
missing) on a flat square against the Euclidean distance, to oriented points on the same square
as a mesh and as a point cloud (.xyz with normals), and its refusals (one line, no output)."""

import math

from clitools import numbers, write_obj

N = 30  # cells per side of [-1, 1]^2: h = 1/15


def square(cli):
    path = cli.out / "square.obj"
    verts = [(-1 + 2 * i / N, -1 + 2 * j / N, 0.0) for j in range(N + 1) for i in range(N + 1)]
    faces = []
    for j in range(N):
        for i in range(N):
            a = j * (N + 1) + i + 1
            faces += [(a, a + 1, a + N + 2), (a, a + N + 2, a + N + 1)]
    write_obj(path, verts, faces)
    return path, verts


def circle(verts, k, arc=1.0, r=0.5):
    """Vertices nearest to k points of the circle, counter-clockwise over `arc` of the turn."""
    out = []
    for i in range(k):
        a = 2 * math.pi * arc * i / (k if arc >= 1 else k - 1)
        p = (r * math.cos(a), r * math.sin(a))
        v = min(range(len(verts)), key=lambda u: (verts[u][0] - p[0]) ** 2 +
                (verts[u][1] - p[1]) ** 2)
        if not out or out[-1] != v:
            out.append(v)
    return out


def check_circle(d, verts, away_from_gap=None):
    """|d| ≈ distance to the circle of radius 0.5, negative inside, positive outside."""
    errs = []
    for v, (x, y, _) in enumerate(verts):
        if away_from_gap and not away_from_gap(math.atan2(y, x) % (2 * math.pi)):
            continue
        exact = math.hypot(x, y) - 0.5
        if abs(exact) > 0.1:
            assert d[v] * exact > 0, (v, d[v], exact)
        if abs(exact) < 0.3:
            errs.append(abs(abs(d[v]) - abs(exact)))
    mean = sum(errs) / len(errs)
    assert mean < 0.02, mean  # the inscribed polygon through grid vertices: ~0.01
    return mean


def test_signed_closed_and_broken_circle(cli):
    mesh, verts = square(cli)
    for name, line, gap in (("closed", "closed 0 ", None),
                            ("broken", "0 ", lambda a: 0.1 * 2 * math.pi < a < 0.7 * 2 * math.pi)):
        loop = circle(verts, 32, 1.0 if gap is None else 0.8)
        curves = cli.out / f"{name}.txt"
        curves.write_text(line + " ".join(map(str, loop)) + "\n")
        out = cli.out / f"{name}.txt.out.txt"
        r = cli.ok("distance", mesh, "--signed", "--curves", curves, "-o", out, "--quiet")
        assert "0 unreached (nan)" in r.out, r.describe()
        d = numbers(out)
        assert len(d) == len(verts)
        for v in loop:
            assert d[v] == 0.0
        check_circle(d, verts, gap)
    # --level-set mean: close to the zero-set result on a closed circle
    out = cli.out / "mean.txt"
    cli.ok("distance", mesh, "--signed", "--curves", cli.out / "closed.txt", "--level-set", "mean",
           "-o", out, "--quiet")
    check_circle(numbers(out), verts)


def test_signed_oriented_points_mesh_and_cloud(cli):
    mesh, verts = square(cli)
    pts = cli.out / "points.txt"
    with open(pts, "w") as f:
        for v in circle(verts, 40):
            x, y, _ = verts[v]
            f.write(f"{v} {x} {y} 0\n")
    cloud = cli.out / "square.xyz"
    cloud.write_text("".join(f"{x} {y} {z} 0 0 1\n" for x, y, z in verts))
    for inp in (mesh, cloud):
        out = cli.out / "pts.txt"
        cli.ok("distance", inp, "--signed", "--points", pts, "-o", out, "--quiet")
        check_circle(numbers(out), verts)


def test_signed_refusals(cli):
    mesh, _ = square(cli)
    bad = cli.out / "bad.txt"
    cli.refuse(2, "--signed needs one of --curves FILE or --points FILE", bad, "distance", mesh,
               "--signed")
    cli.refuse(2, "--points needs --signed", bad, "distance", mesh, "--points", "p.txt")
    cli.refuse(2, "--source cannot be used with --signed", bad, "distance", mesh, "--signed",
               "--source", 0, "--points", "p.txt")
    cli.refuse(2, "--level-set 'up': expected 'zero-set' or 'mean'", bad, "distance", mesh,
               "--signed", "--points", "p.txt", "--level-set", "up")
    pts = cli.out / "p.txt"
    pts.write_text("5 0 0 1\n")
    cli.refuse(1, "normal to the surface", bad, "distance", mesh, "--signed", "--points", pts)
    pts.write_text("5000 1 0 0\n")
    cli.refuse(1, "vertex 5000 is out of range", bad, "distance", mesh, "--signed", "--points",
               pts)


def test_signed_curves_need_an_edge_manifold_mesh(cli):
    bad = cli.out / "bad.txt"
    curves = cli.out / "c.txt"
    curves.write_text("0 0 1\n")
    cli.refuse(1, "edge-manifold", bad, "distance", cli.data / "triple_vierbein.obj", "--signed",
               "--curves", curves)
    mesh, _ = square(cli)
    pts = cli.out / "p.txt"
    pts.write_text("5 1 0 0\n")
    cli.refuse(2, "--curves-out", bad, "distance", mesh, "--signed", "--points", pts,
               "--curves-out", cli.out / "c.obj")
