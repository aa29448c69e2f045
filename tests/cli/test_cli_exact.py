"""`ifem distance --exact`: the exact references of tests/data (1e-9 relative), on the input,
refined and tufted surfaces; the shared references when ../shared/data is present (meshes up to
12k vertices); the memory budget's refusal and the options --exact refuses."""

import math

from clitools import SPOT_VERTICES, count_lines, numbers, obj_vertices, write_obj


def max_rel(values, reference):
    worst = 0.0
    for a, b in zip(values, reference):
        if math.isfinite(b) and b > 0:
            worst = max(worst, abs(a - b) / b)
    return worst


def test_exact_matches_reference(cli):
    out = cli.out / "spot_exact.txt"
    r = cli.ok("distance", cli.spot, "--source", 0, "--exact", "-o", out)
    assert count_lines(out) == SPOT_VERTICES
    assert "exact distance:" in r.err and "windows" in r.err, r.describe()
    ref = numbers(cli.data / "reference" / "spot.src0.exact.txt")
    assert max_rel(numbers(out), ref) <= 1e-9


# The same surface refined, or doubled as a tufted cover: the same distances on input vertices.
def test_exact_refined_and_tufted(cli):
    ref = numbers(cli.data / "reference" / "bunny_npm_lowres.src0.exact.txt")
    mesh = cli.data / "bunny_npm_lowres.obj"
    for extra in (["--refine"], ["--tufted"], ["--no-delaunay"]):
        out = cli.out / "b.txt"
        cli.ok("distance", mesh, "--source", 0, "--exact", "-o", out, "--quiet", *extra)
        assert max_rel(numbers(out), ref) <= 1e-9, extra


def test_exact_shared_references(cli, shared_data):
    checked = 0
    for exact in sorted((shared_data / "reference").glob("*.exact.txt")):
        stem, src = exact.name[:-len(".exact.txt")].rsplit(".src", 1)
        mesh = [m for m in (shared_data / "meshes").glob(stem + ".*")]
        assert mesh, exact
        ref = numbers(exact)
        if len(ref) > 12000 or stem == "conrod":  # large; conrod is cut apart (MANIFEST.md)
            continue
        out = cli.out / "d.txt"
        cli.ok("distance", mesh[0], "--source", src, "--exact", "-o", out, "--quiet")
        assert max_rel(numbers(out), ref) <= 1e-9, exact
        checked += 1
        if checked == 3:  # time: the C++ test covers them all
            break
    assert checked > 0


def test_exact_memory_budget_refused(cli):
    out = cli.out / "x.txt"
    cli.fails_no_partial(r"exact distance: more than [0-9]+ windows .*raise it", out,
                         "distance", cli.spot, "--source", 0, "--exact", "--memory-budget",
                         "0.00001", "-o", out)


def test_exact_refuses_heat_options(cli):
    out = cli.out / "x.txt"
    for extra in (["--time-factor", 2], ["--correction-steps", 1], ["--mixed-precision"]):
        cli.fails("--exact does not take", "distance", cli.spot, "--source", 0, "--exact",
                  "-o", out, *extra)
    cli.fails("--exact does not take --sources-batch", "distance", cli.spot, "--exact",
              "--sources-batch", "s.txt", "-o", out)
    cli.fails("--exact needs --source", "distance", cli.spot, "--exact", "-o", out)
    cli.fails("source", "distance", cli.spot, "--source", 99999, "--exact", "-o", out)


def obj_polylines(path):
    """The 'l' lines of an OBJ as 0-based index lists."""
    return [[int(i) - 1 for i in row.split()[1:]] for row in open(path) if row.startswith("l ")]


# --paths-from: one polyline per vertex, from the vertex to the source, as long as its distance;
# with --isolines the levels of the exact field come out as closed loops on the bunny.
def test_exact_paths_and_isolines(cli):
    mesh = cli.data / "bunny_npm_lowres.obj"
    dist, paths, iso = cli.out / "d.txt", cli.out / "p.obj", cli.out / "iso.obj"
    cli.ok("distance", mesh, "--source", 0, "--exact", "--paths-from", "10,500,1200",
           "--paths-out", paths, "--isolines", 3, "--isolines-out", iso, "-o", dist, "--quiet")
    d = numbers(dist)
    mesh_points, points, lines = obj_vertices(mesh), obj_vertices(paths), obj_polylines(paths)
    assert len(lines) == 3
    for v, line in zip((10, 500, 1200), lines):
        poly = [points[i] for i in line]
        length = sum(math.dist(a, b) for a, b in zip(poly, poly[1:]))
        assert abs(length - d[v]) <= 1e-9 * d[v], (v, length, d[v])
        assert math.dist(poly[0], mesh_points[v]) <= 1e-12
        assert math.dist(poly[-1], mesh_points[0]) <= 1e-12
    loops = obj_polylines(iso)
    assert len(loops) >= 3 and all(loop[0] == loop[-1] for loop in loops)


def test_exact_path_options_refused(cli):
    out, paths = cli.out / "x.txt", cli.out / "p.obj"
    cli.fails("--paths-from needs --exact", "distance", cli.spot, "--source", 0,
              "--paths-from", 1, "--paths-out", paths, "-o", out, rc=2)
    cli.fails("not with --refine", "distance", cli.spot, "--source", 0, "--exact", "--refine",
              "--paths-from", 1, "--paths-out", paths, "-o", out, rc=2)
    cli.fails("go together", "distance", cli.spot, "--source", 0, "--exact", "--paths-from", 1,
              "-o", out, rc=2)
    cli.fails_no_partial("not an input vertex", out, "distance", cli.spot, "--source", 0,
                         "--exact", "--paths-from", 999999, "--paths-out", paths, "-o", out)


def test_zero_area_faces_are_crossed(cli):
    """A flat triangle (0,0), (3,0), (1.5,3) around four coincident copies of (1.5,1), joined by
    zero-area faces. From the apex every copy is 2 away. At margin 0 the windows did not cross
    the zero-area faces (one copy unreached, one 5.16 away); the default margin (1e-12 of the
    mean edge, only because of those faces) gives 2 within 1e-11 (docs/decisions.md D-350)."""
    mesh = cli.out / "coincident_center.obj"
    write_obj(mesh, [(0, 0, 0), (3, 0, 0), (1.5, 3, 0)] + [(1.5, 1, 0)] * 4,
              [(1, 2, 4), (2, 5, 4), (1, 4, 6), (4, 5, 7), (5, 6, 7), (6, 4, 7), (2, 3, 5),
               (1, 6, 3), (6, 5, 3)])
    d = cli.out / "d.txt"
    cli.ok("distance", mesh, "--source", 2, "--exact", "-o", d, "--quiet")
    v = numbers(d)
    assert all(abs(x - 2.0) <= 1e-11 for x in v[3:]), v
    assert abs(v[0] - math.hypot(1.5, 3)) <= 1e-11 and v[2] == 0.0, v
    cli.ok("distance", mesh, "--source", 2, "--exact", "--mollify", 0, "-o", d, "--quiet")
    assert not all(abs(x - 2.0) <= 1e-6 for x in numbers(d)[3:])  # what the default repairs

