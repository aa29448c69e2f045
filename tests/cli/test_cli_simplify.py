"""`ifem simplify` (intrinsic simplification): the .ifem output is a valid coarse intrinsic
triangulation (glued sides agree, every face satisfies the triangle inequality) with the input's
total area, its map puts every input vertex in a coarse face with barycentric coordinates ≥ 0
summing to 1; the PLY's vertices are input vertices at their input positions; --map rows are P's
(≥ 0, summing to 1); nonmanifold input goes through the tufted cover; refusals have their exit
code, one stderr line and no partial output; and every small mesh of ../shared/data simplifies."""

import argparse
import importlib.util
import math
import pathlib

import pytest

from clitools import obj_faces, obj_vertices


def read_ifem(path):
    """The .ifem file's parts, by the sweep script's reader (it also checks the header)."""
    return sweep_module().read_ifem(path)


def heron(a, b, c):
    s = (a + b + c) / 2
    return math.sqrt(max(s * (s - a) * (s - b) * (s - c), 0.0))


def check_ifem(path, n_input, input_area):
    nvc, nf, mult, sides, c2f, points = read_ifem(path)
    assert len(c2f) == nvc and len(points) == n_input and len(set(c2f)) == nvc
    area = 0.0
    for f in range(nf):
        a, b, c = (sides[3 * f + k][2] for k in range(3))
        for x, y, z in ((a, b, c), (b, c, a), (c, a, b)):
            assert x + y - z > 1e-12 * (x + y + z)
        area += heron(a, b, c)
    for h, (tail, twin, length) in enumerate(sides):
        if twin >= 0:
            assert sides[twin][1] == h and sides[twin][2] == length
            nxt = 3 * (twin // 3) + (twin % 3 + 1) % 3
            assert sides[nxt][0] == tail  # glued sides run in opposite directions
    assert area / mult == pytest.approx(input_area, rel=1e-9)
    for v, (face, bary) in enumerate(points):
        assert 0 <= face < nf
        assert min(bary) >= 0.0 and sum(bary) == pytest.approx(1.0, abs=1e-12)
    for c, v in enumerate(c2f):  # a kept vertex is a corner of its face with coordinate 1
        face, bary = points[v]
        corners = [sides[3 * face + k][0] for k in range(3)]
        assert sum(b for k, b in enumerate(bary) if corners[k] == c) == 1.0
    return nvc


def obj_area(path):
    v, f = obj_vertices(path), obj_faces(path)
    total = 0.0
    for t in f:
        p = [v[i - 1] for i in t]
        u = [p[1][k] - p[0][k] for k in range(3)]
        w = [p[2][k] - p[0][k] for k in range(3)]
        cr = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        total += 0.5 * math.sqrt(sum(x * x for x in cr))
    return total


@pytest.mark.parametrize("n", [300, 40])
def test_ifem_output_is_valid_and_keeps_the_area(cli, n):
    r = cli.ok("simplify", cli.spot, "--vertices", n, "-o", "c.ifem", "--quiet")
    assert f"-> {n} " in r.out
    n_input = len(obj_vertices(cli.spot))
    assert check_ifem(cli.out / "c.ifem", n_input, obj_area(cli.spot)) == n


def test_ply_and_map(cli):
    cli.ok("simplify", cli.spot, "--ratio", "0.1", "-o", "c.ply", "--ascii", "--map", "m.txt",
           "--quiet")
    verts = obj_vertices(cli.spot)
    rows = open(cli.out / "c.ply").read().split("\n")
    nvc = int(next(r for r in rows if r.startswith("element vertex")).split()[2])
    assert nvc == round(0.1 * len(verts))
    body = rows[rows.index("end_header") + 1:]
    for line in body[:nvc]:
        x, y, z, vid = (float(t) for t in line.split())
        assert [x, y, z] == pytest.approx(verts[int(vid)], abs=1e-12)
    maps = [r.split() for r in open(cli.out / "m.txt").read().strip().split("\n")]
    assert len(maps) == len(verts)
    for m in maps:
        ids, w = [int(t) for t in m[:3]], [float(t) for t in m[3:]]
        assert all(0 <= i < nvc for i in ids)
        assert min(w) >= 0 and sum(w) == pytest.approx(1.0, abs=1e-12)


def test_tangent_map(cli):
    """--tangent-map: P's coarse vertices, complex weights of P's magnitudes (D-326)."""
    cli.ok("simplify", cli.spot, "--ratio", "0.1", "-o", "c.ifem", "--map", "m.txt",
           "--tangent-map", "t.txt", "--quiet")
    maps = [r.split() for r in open(cli.out / "m.txt").read().strip().split("\n")]
    tmaps = [r.split() for r in open(cli.out / "t.txt").read().strip().split("\n")]
    assert len(tmaps) == len(maps) == len(obj_vertices(cli.spot))
    phases = 0
    for m, t in zip(maps, tmaps):
        assert t[:3] == m[:3]
        z = [complex(float(t[3 + 2 * k]), float(t[4 + 2 * k])) for k in range(3)]
        assert [abs(x) for x in z] == pytest.approx([float(w) for w in m[3:]], abs=1e-12)
        phases += any(abs(x.imag) > 1e-3 for x in z)
    assert phases > len(maps) / 2  # rotations, not the scalar weights


def test_nonmanifold_goes_through_the_tufted_cover(cli):
    path = cli.data / "triple_vierbein.obj"
    r = cli.ok("simplify", path, "--ratio", "0.5", "-o", "c.ifem", "--quiet")
    assert "vertices: 75 ->" in r.out
    _, _, mult, _, _, _ = read_ifem(cli.out / "c.ifem")
    assert mult == 2


@pytest.mark.parametrize("args, regex", [
    ([], "exactly one of --vertices N and --ratio R"),
    (["--vertices", "10", "--ratio", "0.5"], "exactly one of --vertices N and --ratio R"),
    (["--ratio", "0"], "--ratio"),
    (["--ratio", "1.5"], "--ratio"),
    (["--vertices", "2930"], "must be below the input's 2930 vertices"),
])
def test_refusals(cli, args, regex):
    cli.refuse(2, regex, cli.out / "c.ifem", "simplify", cli.spot, *args)


def test_point_cloud_reaches_its_target_and_keeps_its_invariants(cli, tmp_path):
    """spot's vertices as a point cloud (D-290, D-325, D-345): the cover without self-edges
    reaches the target exactly, and the coarse cover is valid (area, Gauss–Bonnet, P)."""
    sweep = sweep_module()
    r = cli.ok("simplify", cli.spot, "--pointcloud", "--knn", "12", "--ratio", "0.2",
               "-o", "c.ifem", "--map", "m.txt", "--quiet")
    assert "vertices: 2930 -> 586 " in r.out and "could not be removed" not in r.out, r.out
    nvc, nf, mult, sides, c2f, points = sweep.read_ifem(cli.out / "c.ifem")
    area, bad = sweep.check_coarse(nvc, nf, mult, sides, c2f, points)
    assert mult == 4 and not bad, bad
    assert not sweep.check_map(cli.out / "m.txt", len(points))
    assert area == pytest.approx(sweep.input_area(str(cli.exe), str(cli.spot), str(tmp_path),
                                                  ["--pointcloud", "--knn", "12"]), rel=1e-9)


def test_point_cloud_names_why_it_stops(cli):
    """Far below (spot's points to 5 %) some points stay; the output counts them and says why
    (links between two neighbours only: no triangulation without a self-edge)."""
    r = cli.ok("simplify", cli.spot, "--pointcloud", "--ratio", "0.05", "-o", "c.ifem", "--quiet")
    assert "could not be removed" in r.out and "self-edge" in r.out, r.out


def test_bad_extension(cli):
    cli.refuse(2, r"\.ply or \.ifem", cli.out / "c.obj", "simplify", cli.spot, "--ratio", "0.5")


def sweep_module():
    """scripts/simplify_sweep.py (the full sweep over ../shared/data), imported for its checks."""
    path = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "simplify_sweep.py"
    spec = importlib.util.spec_from_file_location("simplify_sweep", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_sweep_over_small_shared_inputs(cli, shared_data, tmp_path):
    """The sweep (scripts/simplify_sweep.py) on every mesh and point cloud of ../shared/data
    under 150 kB: each simplifies (only inputs without a surface may be refused), and each
    result keeps the input's area, Gauss–Bonnet per component and P's rows (≥ 0, sum 1)."""
    sweep = sweep_module()
    files = sorted(p for sub in ("meshes", "pointclouds") for p in (shared_data / sub).iterdir()
                   if p.stat().st_size < 150_000)
    args = argparse.Namespace(ratio=0.2, vertices=0, timeout=60, skip_area=False)
    checked, refused = 0, 0
    for p in files:
        r = sweep.run_one(str(cli.exe), str(p), args, str(tmp_path))
        assert r["ok"], f"{p.name}: {r['outcome']}"
        if r["outcome"] == "ok":
            checked += 1
        else:
            refused += 1
    assert checked >= 15 and refused <= 2, (checked, refused)  # it checked something real
