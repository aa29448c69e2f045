"""Data on curves (--curves, solvers/recipes/curves.h): poisson holds u at the curves' values
and stays between them (maximum principle), distance is 0 exactly on the curves, field holds
its directions along them; the curves file's errors name FILE:LINE; every refusal exits with
its code, one stderr line and no output. The curves run along mesh edges of spot (vertex 0's
neighbours 764, 813; 1500's 1496, 1498; 2000's 2001, 126), so FlipOut leaves them as given and
no other input vertex lies on them."""

import math
import sys

from clitools import SPOT_VERTICES, count_lines, grep, head_bytes, lines, numbers, write_obj


def value_at(path, vertex):
    """The value on the line of 0-based `vertex`."""
    return float(lines(path)[vertex])


def is_(a, b):
    """|a − b| ≤ 1e-12."""
    return abs(a - b) <= 1e-12


def within_unit_interval(path):
    values = numbers(path)
    for v, u in enumerate(values):
        assert -1e-12 <= u <= 1 + 1e-12, f"vertex {v}: u = {u}"
    return values


def test_poisson_curves(cli):
    pc = cli.out / "pc.txt"
    pc.write_text("# held at 0, at 1, and 0.25 -> 0.5 -> 0.75\n0 764 0 813\n\n"
                  "1 1496 1500 1498  # a comment\n0.25 0.5 0.75 : 2001 2000 126\n")
    u = cli.out / "pc_u.txt"
    log = cli.ok("poisson", cli.spot, "--curves", pc, "-o", u, "--quiet").out
    assert grep("^wrote .*pc_u.txt: 2930 values, 3 curves", log), log
    assert count_lines(u) == SPOT_VERTICES
    for v in (764, 0, 813):
        assert is_(value_at(u, v), 0)
    for v in (1496, 1500, 1498):
        assert is_(value_at(u, v), 1)
    assert is_(value_at(u, 2001), 0.25)
    assert is_(value_at(u, 2000), 0.5)
    assert is_(value_at(u, 126), 0.75)
    values = within_unit_interval(u)
    assert sum(1 for x in values if 1e-9 < x < 1 - 1e-9) > 2000
    # with --dirichlet on a vertex off the curves, --rhs and --screening too
    bc, rhs, ud = cli.out / "pc_bc.txt", cli.out / "pc_rhs.txt", cli.out / "pc_ud.txt"
    bc.write_text("300 0.3\n")
    rhs.write_text("".join(f"{i % 5 - 2}\n" for i in range(SPOT_VERTICES)))
    cli.ok("poisson", cli.spot, "--curves", pc, "--dirichlet", bc, "--rhs", rhs, "--screening",
           2, "-o", ud, "--quiet")
    assert is_(value_at(ud, 300), 0.3)
    assert is_(value_at(ud, 2000), 0.5)
    assert is_(value_at(ud, 1500), 1)


# .ply (the input mesh + 'u'), the curves as OBJ polylines, progress lines; refined (the curves
# split, never crossed): the same values on the curves and still within them
def test_poisson_curves_ply(cli):
    pcp, ply, obj = cli.out / "pcp.txt", cli.out / "pcp_u.ply", cli.out / "pcp.obj"
    pcp.write_text("0 764 0 813\n1 1496 1500 1498\n")
    r = cli.ok("poisson", cli.spot, "--curves", pcp, "--curves-out", obj, "-o", ply)
    assert grep(r"read .*pcp.txt: 2 curves \(2 paths\)", r.err), r.describe()
    assert grep("curves: 2 inserted", r.err), r.describe()
    assert grep("constrained Delaunay: [0-9]* flips", r.err), r.describe()
    assert grep("u held on 6 curve vertices; 0 conflicting vertices", r.err), r.describe()
    header = head_bytes(ply, 400)
    assert grep("^element vertex 2930", header)
    assert grep("^property double u", header)
    assert grep("^element face 5856", header)
    polylines = [t.split() for t in lines(obj) if t.startswith("l ")]
    assert len(polylines) == 2
    nv = sum(1 for t in lines(obj) if t.startswith("v "))
    assert nv >= 6
    for pl in polylines:
        assert len(pl) >= 3, pl
        assert all(1 <= int(i) <= nv for i in pl[1:]), pl
    assert grep("^wrote .*pcp.obj: 2 curves", r.out), r.describe()

    refined = cli.out / "pcp_r.txt"
    r = cli.ok("poisson", cli.spot, "--curves", pcp, "--refine", "--min-angle", 28, "-o", refined)
    assert grep("refined: 2930 -> [0-9]* vertices", r.err), r.describe()
    for v in (764, 0, 813):
        assert is_(value_at(refined, v), 0)
    for v in (1496, 1500, 1498):
        assert is_(value_at(refined, v), 1)
    assert len(within_unit_interval(refined)) == SPOT_VERTICES


# a slit: u jumps across it (0 on its left, 1 on its right); on its vertices the output is the
# mean of the sides, and u stays within [0, 1]
def test_poisson_curves_slit(cli):
    ps, u = cli.out / "ps.txt", cli.out / "ps_u.txt"
    ps.write_text("slit 0 1 1496 1500 1498\n0.5 764 0 813\n")
    r = cli.ok("poisson", cli.spot, "--curves", ps, "-o", u)
    assert grep("slit copies", r.err), r.describe()
    assert is_(value_at(u, 1500), 0.5)
    assert len(within_unit_interval(u)) == SPOT_VERTICES


def check_zero_on_curves(path):
    values = numbers(path)
    assert len(values) == SPOT_VERTICES
    assert all(d >= 0 for d in values)
    assert sum(1 for d in values if d == 0) == 6


# distance: exactly 0 on the curves' vertices and > 0 everywhere else; .ply with 'distance'
def test_distance_curves(cli):
    dc, d, obj = cli.out / "dc.txt", cli.out / "dc_d.txt", cli.out / "dc.obj"
    dc.write_text("0 764 0 813\n0 1496 1500 1498\n")
    log = cli.ok("distance", cli.spot, "--curves", dc, "-o", d, "--curves-out", obj,
                 "--quiet").out
    assert grep("^wrote .*dc_d.txt: 2930 values, max distance [0-9.e+-]*, 0 unreachable", log), log
    assert count_lines(d) == SPOT_VERTICES
    for v in (764, 0, 813, 1496, 1500, 1498):
        assert is_(value_at(d, v), 0)
    check_zero_on_curves(d)
    assert sum(1 for t in lines(obj) if t.startswith("l ")) == 2
    ply = cli.out / "dc_d.ply"
    cli.ok("distance", cli.spot, "--curves", dc, "-o", ply, "--quiet")
    assert grep("^element vertex 2930", head_bytes(ply, 400))
    assert grep("^property double distance", head_bytes(ply, 400))
    refined = cli.out / "dc_r.txt"
    cli.ok("distance", cli.spot, "--curves", dc, "--refine", "-o", refined, "--quiet")
    check_zero_on_curves(refined)


# the curves file's errors: FILE:LINE and what is wrong, exit 1, one line, no output
def test_curves_bad_file(cli):
    o, spot = cli.out, cli.spot
    (o / "cb_range.txt").write_text("0 764 0 813\n# next: out of range\n1 1500 2930\n")
    cli.refuse(1, r"cb_range.txt:3: vertex 2930 out of range \[0, 2930\)", o / "cb_u.txt",
               "poisson", spot, "--curves", o / "cb_range.txt")
    cli.refuse(1, "cb_range.txt:3: vertex 2930 out of range", o / "cb_d.txt", "distance", spot,
               "--curves", o / "cb_range.txt")
    (o / "cb_bad.txt").write_text("0 764 0 813\n1 1500 x 1498\n")
    cli.refuse(1, "cb_bad.txt:2: 'x' is not a vertex id", o / "cb_u.txt", "poisson", spot,
               "--curves", o / "cb_bad.txt")
    (o / "cb_kw.txt").write_text("closed bezier 0 1 2 3\n")
    cli.refuse(1, "cb_kw.txt:1: 'closed' and 'bezier' exclude each other", o / "cb_u.txt",
               "poisson", spot, "--curves", o / "cb_kw.txt")
    (o / "cb_count.txt").write_text("0 1 : 764 0 813\n")
    cli.refuse(1, "cb_count.txt:1: 2 values for 3 vertices", o / "cb_u.txt", "poisson", spot,
               "--curves", o / "cb_count.txt")
    (o / "cb_empty.txt").write_text("# nothing\n\n")
    cli.refuse(1, "cb_empty.txt: no curve in the file", o / "cb_u.txt", "poisson", spot,
               "--curves", o / "cb_empty.txt")
    cli.refuse(1, "no_such_curves.txt: cannot open", o / "cb_u.txt", "poisson", spot,
               "--curves", o / "no_such_curves.txt")
    cli.refuse(1, "no_such_curves.txt: cannot open", o / "cb_d.txt", "distance", spot,
               "--curves", o / "no_such_curves.txt")


# inputs curves cannot use: a nonmanifold mesh (three triangles on one edge), a point cloud
def test_curves_refused_inputs(cli):
    o, spot = cli.out, cli.spot
    (o / "cr.txt").write_text("0 0 2\n")
    cli.refuse(1, "manifold", o / "cr_u.txt", "poisson", cli.fan3, "--curves", o / "cr.txt")
    cli.refuse(1, "manifold", o / "cr_d.txt", "distance", cli.fan3, "--curves", o / "cr.txt")
    points = cli.spot_points("cr_points.xyz")
    cli.refuse(1, "point cloud|no faces", o / "cr_u.txt", "poisson", points, "--curves",
               o / "cr.txt")
    # a Dirichlet vertex on a curve; --curves-out that cannot be written (u.txt is removed again)
    (o / "cr_ok.txt").write_text("0 764 0 813\n1 1496 1500 1498\n")
    (o / "cr_bc.txt").write_text("1500 0.3\n")
    cli.refuse(1, "Dirichlet vertex 1500 lies on a curve", o / "cr_u.txt", "poisson", spot,
               "--curves", o / "cr_ok.txt", "--dirichlet", o / "cr_bc.txt")
    cli.refuse(1, "cannot write .*no_such_dir/c.obj.tmp", o / "cr_u.txt", "poisson", spot,
               "--curves", o / "cr_ok.txt", "--curves-out", o / "no_such_dir/c.obj")
    cli.refuse(1, "cannot write .*no_such_dir/c.obj.tmp", o / "cr_d.txt", "distance", spot,
               "--curves", o / "cr_ok.txt", "--curves-out", o / "no_such_dir/c.obj")
    # two curves whose geodesics run along one edge (seen on spot: 12 -> 400 and 500 -> 900 ->
    # 1300 both take the edge 12-900): refused naming both lines
    (o / "cr_overlap.txt").write_text("0.5 12 400 770\nclosed 1 500 900 1300\n")
    cli.refuse(1, "cr_overlap.txt:2 and curve at .*cr_overlap.txt:1 share the edge",
               o / "cr_u.txt", "poisson", spot, "--curves", o / "cr_overlap.txt")


# the command line: options that make no sense with --curves, --curves-out without --curves or
# not .obj (exit 2, before any work)
def test_curves_usage(cli):
    o, spot = cli.out, cli.spot
    cu = o / "cu.txt"
    cu.write_text("0 764 0 813\n")
    cli.refuse(2, "--source cannot be used with --curves: the curves are the sources",
               o / "cu_d.txt", "distance", spot, "--curves", cu, "--source", 0)
    cli.refuse(2, r"missing --source I\[,J,...\] \(or --sources-batch FILE or --curves FILE",
               o / "cu_d.txt", "distance", spot)
    for opt in (["--tufted"], ["--pointcloud"], ["--no-delaunay"], ["--knn", "5"],
                ["--relax", "1"], ["--max-edge", "0.1"]):
        cli.refuse(2, f"{opt[0]} cannot be used with --curves: ", o / "cu_u.txt", "poisson",
                   spot, "--curves", cu, *opt)
        cli.refuse(2, f"{opt[0]} cannot be used with --curves: ", o / "cu_d.txt", "distance",
                   spot, "--curves", cu, *opt)
    cli.refuse(2, "--curves-out writes the curves of --curves FILE, which was not given",
               o / "cu_u.txt", "poisson", spot, "--curves-out", o / "cu.obj")
    cli.refuse(2, "--curves-out writes the curves of --curves", o / "cu_d.txt", "distance",
               spot, "--source", 0, "--curves-out", o / "cu.obj")
    cli.refuse(2, "--curves-out '.*cu.ply': the output must end in .obj", o / "cu_u.txt",
               "poisson", spot, "--curves", cu, "--curves-out", o / "cu.ply")
    assert not (o / "cu.obj").exists()


def unit_rows(path, rows):
    """`rows` lines, each a 3-vector of length 1 (to 1e-9)."""
    assert count_lines(path) == rows
    for i, line in enumerate(lines(path)):
        x, y, z = (float(t) for t in line.split()[:3])
        n = math.sqrt(x * x + y * y + z * z)
        assert 1 - 1e-9 <= n <= 1 + 1e-9, f"row {i}: length {n}"


# field --curves: a cross field held along curves on spot (Poincaré–Hopf still 8 quarter
# turns), the curves written with --curves-out, .txt rows of unit vectors; the curves file's
# values are ignored, a malformed line is named FILE:LINE, the options curves cannot use are
# refused before any work, and so is a mesh curves cannot be drawn on
def test_field_curves(cli):
    o, spot = cli.out, cli.spot
    fcu, ply, obj = o / "fcu.txt", o / "fcu.ply", o / "fcu.obj"
    fcu.write_text("0 764 0 813\n1 1496 1500 1498\nbezier 0 2001 2000 126 300\n")
    r = cli.ok("field", spot, "--symmetry", 4, "--curves", fcu, "--curves-out", obj, "-o", ply)
    assert grep(r"read .*fcu.txt: 3 curves \(2 paths, 1 Bézier curve\)", r.err), r.describe()
    assert grep("curves: 3 inserted", r.err), r.describe()
    assert grep("field in .* s: [0-9]* vertices held", r.err), r.describe()
    assert grep("total index 8/4", r.out), r.describe()
    assert grep("wrote .*fcu.obj: 3 curves", r.out), r.describe()
    assert grep("^property double fx", head_bytes(ply, 400))
    assert sum(1 for t in lines(obj) if t.startswith("l ")) == 3
    txt = o / "fcu.txt.out.txt"
    r = cli.ok("field", spot, "--curves", fcu, "--align-boundary", "-o", txt, "--quiet")
    assert grep("total index 2/1", r.out), r.describe()
    unit_rows(txt, SPOT_VERTICES)
    (o / "fcu_bad.txt").write_text("0 764 0 813\nbezier=x 0 1 2\n")
    cli.refuse(1, "fcu_bad.txt:2: ", o / "fcu_bad.ply", "field", spot, "--curves",
               o / "fcu_bad.txt")
    cli.refuse(2, "--tufted cannot be used with --curves", o / "fcu_t.ply", "field", spot,
               "--curves", fcu, "--tufted")
    cli.refuse(2, "--curves-out writes the curves of --curves FILE", o / "fcu_o.ply", "field",
               spot, "--curves-out", obj)
    (o / "fcu1.txt").write_text("0 0 2\n")
    cli.refuse(1, "curves need an edge-manifold, orientable mesh", o / "fcu_f.ply", "field",
               cli.fan3, "--curves", o / "fcu1.txt")


def holey_scan_files(cli, seed):
    """tests/data/make_holey_scan.py's mesh (many small holes) and hard curves, written out."""
    sys.path.insert(0, str(cli.data))
    import make_holey_scan as m
    V, F = m.holey_scan(seed=seed)
    mesh, curves = cli.out / f"holey{seed}.obj", cli.out / f"holey{seed}.txt"
    write_obj(mesh, V, [tuple(i + 1 for i in f) for f in F])
    curves.write_text(m.curves_text(m.hard_curves(V)))
    return mesh, curves


# Refined curve problems keep the maximum principle: curve and boundary edges with negative cotan
# weights are split (conforming refinement). --no-conform keeps them: there the holes and the
# sharp curves leave negative weights and u leaves [0, 1] by far more than rounding.
def test_poisson_curves_refine_conforms(cli):
    mesh, curves = holey_scan_files(cli, 4)
    u, u0 = cli.out / "holey_u.txt", cli.out / "holey_u0.txt"
    r = cli.ok("poisson", mesh, "--curves", curves, "--refine", "-o", u)
    assert grep(r"[1-9][0-9]* conforming splits", r.err), r.describe()
    assert not grep("negative cotan weights: ", r.err), r.describe()
    assert not grep("keep a negative cotan weight", r.err), r.describe()
    within_unit_interval(u)
    r0 = cli.ok("poisson", mesh, "--curves", curves, "--refine", "--no-conform", "-o", u0)
    assert grep("negative cotan weights: [1-9][0-9]* on curve edges", r0.err), r0.describe()
    assert not grep("conforming splits", r0.err), r0.describe()
    values = numbers(u0)
    assert min(values) < -1e-6 or max(values) > 1 + 1e-6, (min(values), max(values))
    cli.refuse(2, "--no-conform turns off a step of --refine, which was not given",
               cli.out / "holey_u1.txt", "poisson", mesh, "--curves", curves, "--no-conform")
    cli.refuse(2, "--no-conform applies to --curves with --refine; --curves was not given",
               cli.out / "holey_u1.txt", "poisson", mesh, "--refine", "--no-conform")
