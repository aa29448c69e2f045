"""`ifem trace` (straight geodesics from a point in a direction): on a flat grid the ray is the
straight segment of the length asked (end point exact to 1e-12, in every output format and in
--json); on a prism (a polyhedral cylinder, whose side unrolls onto a strip) a helix ends where
the unrolled line does; the end token traces back to the start; and every refusal has its exit
code, one stderr line and no partial output."""

import json
import math

import pytest

from clitools import count_lines, head_bytes, lines, obj_vertices, write_obj


def grid(path, nx=8, ny=6, w=4.0, h=3.0):
    """A flat nx × ny grid on [0, w] × [0, h] (z = 0), two triangles a cell."""
    verts = [(w * i / nx, h * j / ny, 0.0) for j in range(ny + 1) for i in range(nx + 1)]
    faces = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i + 1
            b, c, d = a + 1, a + nx + 1, a + nx + 2
            faces += [(a, b, d), (a, d, c)] if (i + j) % 2 else [(a, b, c), (b, d, c)]
    write_obj(path, verts, faces)
    return verts, faces


def prism(path, n=12, rings=20, h=0.5):
    """An open prism of n sides (circumradius 1), `rings` rows of height h."""
    verts = [(math.cos(2 * math.pi * j / n), math.sin(2 * math.pi * j / n), i * h)
             for i in range(rings + 1) for j in range(n)]
    faces = []
    for i in range(rings):
        for j in range(n):
            a, b = i * n + j + 1, i * n + (j + 1) % n + 1
            faces += [(a, b, b + n), (a, b + n, a + n)]
    write_obj(path, verts, faces)


def prism_point(u, z, n=12):
    """The prism's point at unrolled coordinates (u along the strip, z up)."""
    s = 2 * math.sin(math.pi / n)
    u %= n * s
    k = min(int(u / s), n - 1)
    t = (u - k * s) / s
    a0, a1 = 2 * math.pi * k / n, 2 * math.pi * (k + 1) / n
    return ((1 - t) * math.cos(a0) + t * math.cos(a1), (1 - t) * math.sin(a0) + t * math.sin(a1),
            z)


def length3d(points):
    return sum(math.dist(p, q) for p, q in zip(points, points[1:]))


def trace_json(cli, *args):
    return json.loads(cli.ok("trace", *args, "--json", "--quiet").out)


def test_trace_flat_grid_is_straight(cli):
    grid(cli.out / "grid.obj")
    for deg in (0, 45, 137.5):  # along an edge, a cell diagonal (through vertices), oblique
        d = (math.cos(math.radians(deg)), math.sin(math.radians(deg)))
        doc = trace_json(cli, "grid.obj", "--from", "31", "--direction",
                         f"{d[0]!r},{d[1]!r},0.4", "--length", "1.25", "-o", "ray.obj")
        ray = doc["rays"][0]
        start = (2.0, 1.5, 0.0)  # vertex 31: column 4, row 3 of the 9 × 7 vertices
        want = (start[0] + 1.25 * d[0], start[1] + 1.25 * d[1], 0.0)
        assert math.dist(ray["end"]["position"], want) < 1e-12, (deg, ray)
        assert abs(ray["length"] - 1.25) < 1e-12
        assert not ray["hit_boundary"]
        pts = obj_vertices(cli.out / "ray.obj")
        assert len(pts) == ray["points"]
        assert abs(length3d(pts) - 1.25) < 1e-12
        assert math.dist(pts[0], start) < 1e-15 and math.dist(pts[-1], want) < 1e-12
        # the end token traces back to the start
        back = trace_json(cli, "grid.obj", "--from", ray["end"]["token"], "--direction",
                          f"{-d[0]!r},{-d[1]!r},0", "--length", "1.25")
        assert math.dist(back["rays"][0]["end"]["position"], start) < 1e-12


def test_trace_text_formats_and_several_rays(cli):
    grid(cli.out / "grid.obj")
    (cli.out / "dirs.txt").write_text("# three rays\n1 0 0\n0 1 0\n\n-1 -1 0  # a diagonal\n")
    r = cli.ok("trace", "grid.obj", "--from", "face:20:0.25:0.25", "--directions", "dirs.txt",
               "--length", "0.6", "-o", "rays.obj")
    assert r.out.count("\nray ") + r.out.startswith("ray ") == 3, r.out
    assert "wrote rays.obj: 3 rays" in r.out
    assert sum(1 for line in lines(cli.out / "rays.obj") if line.startswith("l ")) == 3
    cli.ok("trace", "grid.obj", "--from", "face:20:0.25:0.25", "--directions", "dirs.txt",
           "--length", "0.6", "-o", "rays.ply")
    assert head_bytes(cli.out / "rays.ply", 3) == "ply"
    assert "element edge" in head_bytes(cli.out / "rays.ply", 400)
    cli.ok("trace", "grid.obj", "--from", "face:20:0.25:0.25", "--directions", "dirs.txt",
           "--length", "0.6", "-o", "rays.txt")
    blocks = (cli.out / "rays.txt").read_text().strip("\n").split("\n\n")
    assert len(blocks) == 3
    for b in blocks:
        pts = [tuple(float(x) for x in line.split()) for line in b.split("\n")]
        assert abs(length3d(pts) - 0.6) < 1e-12
    assert count_lines(cli.out / "rays.txt") > 6


def test_trace_boundary_stops_or_slides(cli):
    grid(cli.out / "grid.obj")
    start = "face:20:0.25:0.25"
    doc = trace_json(cli, "grid.obj", "--from", start, "--direction", "1,0,0", "--length", "9")
    ray = doc["rays"][0]
    assert ray["hit_boundary"] and abs(ray["end"]["position"][0] - 4.0) < 1e-12
    assert ray["length"] < 9
    r = cli.ok("trace", "grid.obj", "--from", start, "--direction", "1,0,0", "--length", "9")
    assert "stopped at the boundary" in r.out
    slid = trace_json(cli, "grid.obj", "--from", start, "--direction", "1,0.3,0", "--length",
                      "9", "--slide")["rays"][0]
    assert slid["slides"] > 0 and slid["length"] > ray["length"]
    assert abs(slid["end"]["position"][0] - 4.0) < 1e-12  # on the side it slid along


@pytest.mark.parametrize("climb", [0.1, -0.03, 0.5])
def test_trace_prism_helix_unrolls(cli, climb):
    prism(cli.out / "prism.obj")
    n, s = 12, 2 * math.sin(math.pi / 12)
    # face 48: row 2, panel 0, corners (24, 25, 37): the point 0.6·x24 + 0.2·x25 + 0.2·x37
    u0, z0 = 0.4 * s, 1.0 + 0.2 * 0.5
    lu, lz = math.cos(math.atan(climb)), math.sin(math.atan(climb))
    along = (math.cos(2 * math.pi / n) - 1, math.sin(2 * math.pi / n))
    norm = math.hypot(*along)
    d = (lu * along[0] / norm, lu * along[1] / norm, lz)
    length = min(2.5 * n * s, 8.5 / abs(lz))
    ray = trace_json(cli, "prism.obj", "--from", "face:48:0.2:0.2", "--direction",
                     ",".join(repr(x) for x in d), "--length", repr(length))["rays"][0]
    want = prism_point(u0 + length * lu, z0 + length * lz)
    assert math.dist(ray["end"]["position"], want) < 1e-11, (ray, want)
    assert abs(ray["length"] - length) < 1e-12 * length


BAD = [
    (2, r"--direction '0,0,0': the zero direction", ["--from", "3", "--direction", "0,0,0"]),
    (2, r"--direction '1,2' is not a direction", ["--from", "3", "--direction", "1,2"]),
    (1, r"along the surface normal", ["--from", "face:20:0.25:0.25", "--direction", "0,0,-2"]),
    (2, r"--length", ["--from", "3", "--direction", "1,0,0", "--length", "-1"]),
    (2, r"--from vertex 99 out of range \[0, 63\)", ["--from", "99", "--direction", "1,0,0"]),
    (2, r"face 96 out of range \[0, 96\)", ["--from", "face:96:0:0", "--direction", "1,0,0"]),
    (2, r"--from 'face:1:x:0' is not a point", ["--from", "face:1:x:0", "--direction", "1,0,0"]),
    (2, r"exactly one of --direction", ["--from", "3"]),
    (1, r"points off the surface at boundary vertex 3",
     ["--from", "3", "--direction", "0,-1,0"]),
]


@pytest.mark.parametrize("rc,regex,args", BAD)
def test_trace_refusals(cli, rc, regex, args):
    grid(cli.out / "grid.obj")
    if "--length" not in args:
        args = args + ["--length", "1"]
    r = cli.refuse(rc, regex, cli.out / "ray.obj", "trace", "grid.obj", *args)
    assert r.out == ""


def test_trace_refused_inputs(cli):
    grid(cli.out / "grid.obj")
    (cli.out / "dirs.txt").write_text("1 0 0\n1 0\n")
    cli.refuse(1, r"dirs.txt:2: '1 0' is not a direction", cli.out / "ray.obj", "trace",
               "grid.obj", "--from", "3", "--directions", "dirs.txt", "--length", "1")
    (cli.out / "dirs.txt").write_text("1 0 0\n0 0 1\n")  # the second is along the normal
    cli.refuse(1, r"ray 2: direction .* along the surface normal", cli.out / "ray.obj", "trace",
               "grid.obj", "--from", "face:20:0.25:0.25", "--directions", "dirs.txt",
               "--length", "1")
    write_obj(cli.out / "fin.obj", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)],
              [(1, 2, 3), (2, 1, 4), (1, 2, 5)])
    cli.refuse(1, r"trace needs an edge-manifold.*3 incident faces", cli.out / "ray.obj",
               "trace", "fin.obj", "--from", "0", "--direction", "0,1,0", "--length", "1")


def test_trace_help_teaches(cli):
    r = cli.ok("trace", "--help")
    for word in ("exponential map", "face:F:u:v", "angle-weighted vertex normal", "--slide",
                 "--directions", "nonmanifold", "examples:"):
        assert word in r.out, word
