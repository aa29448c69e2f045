"""`ifem geodesic` (FlipOut): every output format, loops, face points, networks, Bézier curves,
single-source lengths, and every refusal (exit code, one stderr line, no partial output).
Lengths are checked against the 3D length of the written polylines and, where it is known,
against the exact value (a cylinder's waist, a straight segment on a flat grid)."""

import math
import re

import pytest

from clitools import (SPOT_VERTICES, close, count_lines, grep, head_bytes, lines, numbers,
                      obj_faces, obj_vertices, same_point, write_obj)


def polylines(path):
    """The curves of a .txt polyline file (curves separated by an empty line), as point lists."""
    curves, current = [], []
    for line in lines(path):
        fields = line.split()
        if not fields:
            if current:
                curves.append(current)
            current = []
            continue
        current.append(tuple(float(x) for x in fields[:3]))
    if current:
        curves.append(current)
    return curves


def length3d(points):
    return sum(math.dist(p, q) for p, q in zip(points, points[1:]))


def final_length(log, curve=1):
    """The length after FlipOut printed on the `curve N ... -> LENGTH, ...` line."""
    for line in log.split("\n"):
        m = re.match(rf"^curve {curve} .* -> ([0-9.e+-]*),", line)
        if m:
            return float(m.group(1))
    raise AssertionError(f"no 'curve {curve} ... -> LENGTH,' line in:\n{log}")


def point(text):
    return tuple(float(x) for x in text.split())


# a path through waypoints: the OBJ's polyline (one 'l' line through every 'v') has the printed
# length; the same path as .txt and .ply holds the same points
def test_geodesic(cli):
    obj = cli.out / "spot_geo.obj"
    log = cli.ok("geodesic", cli.spot, "--path", "0,657,1500", "-o", obj, "--quiet").out
    text = lines(obj)
    n = sum(1 for t in text if t.startswith("v "))
    l_lines = [t for t in text if t.startswith("l ")]
    assert len(l_lines) == 1
    assert len(l_lines[0].split()) == n + 1
    assert grep(rf"^curve 1 \(path through 3 points\): length .*, {n} points", log), log
    assert grep(r"^FlipOut: [0-9]* flips, [0-9]* iterations, stopped: [a-z ]*, .* s$", log), log
    assert grep(rf"^wrote .*spot_geo.obj: 1 curve, {n} points, length ", log), log
    length = final_length(log)
    assert close(length3d(obj_vertices(obj)), length)

    txt = cli.out / "spot_geo.txt"
    cli.ok("geodesic", cli.spot, "--path", "0,657,1500", "-o", txt, "--quiet")
    assert count_lines(txt) == n
    assert sum(1 for t in lines(txt) if t) == n
    assert close(length3d(polylines(txt)[0]), length)

    ply = cli.out / "spot_geo.ply"
    cli.ok("geodesic", cli.spot, "--path", "0,657,1500", "-o", ply, "--quiet")
    header_end = lines(ply).index("end_header")
    header, body = lines(ply)[:header_end], lines(ply)[header_end + 1:]
    assert "format ascii 1.0" in header[:12]
    assert f"element vertex {n}" in header
    assert f"element edge {n - 1}" in header
    verts = [t for t in body if len(t.split()) == 3]
    edges = [t for t in body if len(t.split()) == 2]
    assert len(verts) == n and len(edges) == n - 1
    for a, b in zip(verts, lines(txt)):
        assert same_point(point(a), point(b)), (a, b)


# a loop closes: first point == last (.txt), the 'l' line ends where it starts (.obj), the
# printed length is the polyline's; a free loop on spot (genus 0: contractible) never gets longer
# and either stays a closed curve or is reported collapsed
def test_geodesic_loop(cli):
    txt = cli.out / "spot_loop.txt"
    log = cli.ok("geodesic", cli.spot, "--path", "0,657,1500", "--loop", "--pin", "-o", txt,
                 "--quiet").out
    assert grep(r"^curve 1 \(loop through 3 points, pinned\): length", log), log
    pts = polylines(txt)[0]
    assert same_point(pts[0], pts[-1])
    assert close(length3d(pts), final_length(log))
    obj = cli.out / "spot_loop.obj"
    cli.ok("geodesic", cli.spot, "--path", "0,657,1500", "--loop", "--pin", "-o", obj, "--quiet")
    l_line = [t for t in lines(obj) if t.startswith("l ")][0].split()
    assert l_line[1] == "1" and l_line[-1] == "1" and len(l_line) > 4, l_line
    assert len(obj_vertices(obj)) == count_lines(txt) - 1

    free = cli.out / "spot_free.txt"
    log = cli.ok("geodesic", cli.spot, "--path", "0,657,1500", "--loop", "-o", free,
                 "--quiet").out
    m = re.search(r"^curve 1 \(loop through 3 points\): length ([^ ]*) -> ([^,]*),", log, re.M)
    assert m, log
    before, after = float(m.group(1)), float(m.group(2))
    assert 0 <= after <= before, (before, after)
    if "collapsed" not in log:
        pts = polylines(free)[0]
        assert same_point(pts[0], pts[-1])
        assert close(length3d(pts), after)


# a loop around an open cylinder (24-gon of radius 1, 6 rings) started through three vertices on
# different rings shrinks to a waist circle: the 24-gon's perimeter 48 sin(π/24)
def test_geodesic_cylinder(cli):
    n, m = 24, 6
    verts = [(math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n), j)
             for j in range(m) for i in range(n)]
    faces = []
    for j in range(m - 1):
        for i in range(n):
            a, b = j * n + i + 1, j * n + (i + 1) % n + 1
            c, d = a + n, b + n
            faces += [(a, b, d), (a, d, c)]
    mesh = cli.out / "cylinder.obj"
    write_obj(mesh, verts, faces)
    txt = cli.out / "cyl_loop.txt"
    log = cli.ok("geodesic", mesh, "--path", "24,104,64", "--loop", "-o", txt, "--quiet").out
    length = final_length(log)
    assert close(length, 48 * math.sin(math.pi / 24)), length
    pts = polylines(txt)[0]
    assert close(length3d(pts), length)
    assert same_point(pts[0], pts[-1])


# a face point: inserted at (1−u−v)·p0 + u·p1 + v·p2 of the file's face (computed here from the
# OBJ), reported with that position, and the path starts there
def test_geodesic_face_point(cli):
    txt = cli.out / "spot_face.txt"
    log = cli.ok("geodesic", cli.spot, "--path", "face:100:0.25:0.5,1500", "-o", txt,
                 "--quiet").out
    p = obj_vertices(cli.spot)
    a, b, c = obj_faces(cli.spot)[100]
    expected = tuple(.25 * p[a - 1][k] + .25 * p[b - 1][k] + .5 * p[c - 1][k] for k in range(3))
    pts = polylines(txt)[0]
    assert math.dist(expected, pts[0]) <= 1e-9, (expected, pts[0])
    assert grep(r"^inserted face:100:0.25:0.5 as vertex 2930 at \(", log), log
    m = re.search(r"^inserted .* at \((.*)\)$", log, re.M)
    assert m, log
    assert same_point(expected, tuple(float(x) for x in m.group(1).replace(",", " ").split()))
    assert close(length3d(pts), final_length(log))


# --start: from spot's vertex 2222 to 0 the shortest edge path goes round a vertex on the other
# side than the shortest geodesic, so FlipOut from it (--start dijkstra) ends 0.37% longer than
# the exact distance (tests/data/reference/spot.src0.exact.txt); the default start (best) finds
# the shortest geodesic
def test_geodesic_start(cli):
    exact = float(lines(cli.data / "reference" / "spot.src0.exact.txt")[2222])
    out = {}
    for start in ["dijkstra", "best"]:
        txt = cli.out / f"start_{start}.txt"
        log = cli.ok("geodesic", cli.spot, "--path", "2222,0", "--start", start, "-o", txt,
                     "--quiet").out
        out[start] = final_length(log)
        assert close(length3d(polylines(txt)[0]), out[start])
    assert abs(out["best"] - exact) <= 1e-6 * exact, (out, exact)
    assert out["dijkstra"] > exact * (1 + 1e-3), (out, exact)
    log = cli.ok("geodesic", cli.spot, "--path", "2222,0", "-o", cli.out / "start.txt").err
    assert grep(r"^ifem: start guide \(exact or heat distance\) in [0-9.e-]* s$", log), log
    kept = r"^ifem: start won: (shortest edge path|(exact geodesic|descent) to (b|a, reversed), " \
           r"(shorter|left|right) side)$"
    assert grep(kept, log), log


# a network of two paths sharing an endpoint (comments and blank lines skipped): two curves,
# the second starts where the first ends, each as long as printed
def test_geodesic_network(cli):
    net = cli.out / "net.txt"
    net.write_text("# two paths meeting at vertex 657\n\npath 0 657   # first\n  path\t657 1500\n")
    out = cli.out / "net.txt.out.txt"
    log = cli.ok("geodesic", cli.spot, "--network", net, "-o", out, "--quiet").out
    assert grep(r"^curve 1 \(path through 2 points \(.*net.txt:3\)\): length", log), log
    assert grep(r"^curve 2 \(path through 2 points \(.*net.txt:4\)\): length", log), log
    assert grep(r"^wrote .*: 2 curves, ", log), log
    assert lines(out).count("") == 1
    curves = polylines(out)
    assert len(curves) == 2
    assert same_point(curves[0][-1], curves[1][0])
    for k, curve in enumerate(curves):
        assert close(length3d(curve), final_length(log, k + 1))
    obj = cli.out / "net.obj"
    cli.ok("geodesic", cli.spot, "--network", net, "-o", obj, "--quiet")
    assert sum(1 for t in lines(obj) if t.startswith("l ")) == 2


# a geodesic Bézier curve with collinear control points on a flat grid (quads split along the
# other diagonal, so the segment crosses faces) is the straight segment: length 10√2; degree 2,
# 2 rounds: 2·2² + 1 control points
def test_geodesic_bezier(cli):
    n = 11
    verts = [(i, j, 0) for j in range(n) for i in range(n)]
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i + 1
            b, c = a + 1, a + n
            faces += [(a, b, c), (b, c + 1, c)]
    mesh = cli.out / "grid.obj"
    write_obj(mesh, verts, faces)
    txt = cli.out / "grid_bezier.txt"
    log = cli.ok("geodesic", mesh, "--path", "0,48,120", "--bezier", 2, "-o", txt, "--quiet").out
    assert grep("^Bézier: 9 control points after 2 rounds", log), log
    m = re.search(r"^curve 1 \(Bézier curve of degree 2, 2 rounds\): length .* -> ([0-9.e+-]*),",
                  log, re.M)
    assert m, log
    length = float(m.group(1))
    assert close(length, 10 * math.sqrt(2)), length
    pts = polylines(txt)[0]
    assert close(length3d(pts), length)
    assert same_point(pts[0], (0, 0, 0))
    assert same_point(pts[-1], (10, 10, 0))


# single-source lengths from vertex 0: one per vertex, 0 at the source, ≥ 0, and never shorter
# than the straight 3D segment from the source (a true lower bound); .ply: the mesh + property
def test_geodesic_all_from(cli):
    txt = cli.out / "spot_ss.txt"
    log = cli.ok("geodesic", cli.spot, "--all-from", 0, "-o", txt, "--quiet").out
    assert grep(r"^wrote .*spot_ss.txt: 2930 values, max length [0-9.e+-]*, 0 unreachable",
                log), log
    assert count_lines(txt) == SPOT_VERTICES
    assert lines(txt)[0] == "0"
    p = obj_vertices(cli.spot)
    values = numbers(txt)
    assert len(values) == len(p) == SPOT_VERTICES
    for v, (q, d) in enumerate(zip(p, values)):
        chord = math.dist(p[0], q)
        assert d >= 0 and d + 1e-9 >= chord, f"vertex {v}: {d} < {chord}"
    # the default is the exact distance (the shortest geodesics): FlipOut's geodesics are never
    # shorter, and equal on most vertices; the exact command gives the same lengths
    assert grep(r"^single-source geodesics from vertex 0: exact distance, [0-9]+ windows", log)
    flip = cli.out / "spot_ss_flip.txt"
    log = cli.ok("geodesic", cli.spot, "--all-from", 0, "--single-source-flipout", "-o", flip,
                 "--quiet").out
    assert grep(r"^single-source geodesics from vertex 0: FlipOut, [0-9]+ flips", log), log
    flipped = numbers(flip)
    assert all(f >= d * (1 - 1e-9) for d, f in zip(values, flipped))
    assert sum(abs(f - d) <= 1e-9 * max(d, 1e-300) for d, f in zip(values, flipped)) >= 0.9 * len(
        values)
    exact = cli.out / "spot_exact.txt"
    cli.ok("distance", cli.spot, "--source", 0, "--exact", "-o", exact, "--quiet")
    assert all(abs(a - b) <= 1e-12 * max(values) for a, b in zip(numbers(exact), values))
    ply = cli.out / "spot_ss.ply"
    cli.ok("geodesic", cli.spot, "--all-from", 0, "-o", ply, "--quiet")
    header = head_bytes(ply, 400)
    assert grep("^element vertex 2930", header)
    assert grep("^property double geodesic_length", header)
    assert grep("^element face 5856", header)


# refusals on the command line (exit 2, before any work): (regex, output name, arguments)
USAGE_REFUSALS = [
    ("--path '3': needs at least two points", "g1.obj", ["--path", "3", "--quiet"]),
    (r"--path vertex 2930 out of range \[0, 2930\) \(the input has 2930 vertices\)", "g1.obj",
     ["--path", "0,2930", "--quiet"]),
    (r"'face:5856:0.1:0.1': face 5856 out of range \[0, 5856\)", "g1.obj",
     ["--path", "0,face:5856:0.1:0.1", "--quiet"]),
    ("points 2 and 3 are the same point '5'", "g1.obj", ["--path", "0,5,5", "--quiet"]),
    ("points 3 and 1 are the same point '0'", "g1.obj", ["--path", "0,5,0", "--loop", "--quiet"]),
    (r"--all-from 2930: vertex out of range \[0, 2930\)", "g1.txt",
     ["--all-from", "2930", "--quiet"]),
    ("--all-from writes one length per vertex", "g1.obj", ["--all-from", "0", "--quiet"]),
    ("give exactly one of --path, --network, --all-from", "g1.obj", ["--quiet"]),
    ("--single-source-flipout goes with --all-from", "g1.obj",
     ["--path", "0,1", "--single-source-flipout", "--quiet"]),
    ("give exactly one of --path, --network, --all-from", "g1.txt",
     ["--path", "0,1", "--all-from", "0", "--quiet"]),
    ("--bezier takes --path's points as control points", "g1.obj",
     ["--path", "0,1,2", "--loop", "--bezier", "2"]),
    ("--pin keeps a loop's points", "g1.obj", ["--path", "0,1", "--pin"]),
    ("--start 'fast': expected 'best', 'guided' or 'dijkstra'", "g1.obj",
     ["--path", "0,1", "--start", "fast"]),
]


@pytest.mark.parametrize("regex,name,args", USAGE_REFUSALS,
                         ids=[" ".join(args) for _, _, args in USAGE_REFUSALS])
def test_geodesic_usage_refusals(cli, regex, name, args):
    out = cli.out / name
    cli.fails_no_partial(regex, out, "geodesic", cli.spot, *args, "-o", out, rc=2)


# malformed points: each token refused with exit 2 and what a point is
def test_geodesic_bad_points(cli):
    out = cli.out / "bad_p.obj"
    for p in ["3x", "-1", "", "face:1:2", "face:x:0.1:0.1", "face:-1:0.1:0.1", "face:1:nan:0.1",
              "face:1:0.1:inf", "face:1:0.7:0.7", "face:1:-0.1:0.2", "face:1:0.1:0.1:0.1",
              "face:1e3:0.1:0.1", "face:99999999999:0:0", "2.5"]:
        r = cli.run("geodesic", cli.spot, "--path", f"0,{p}", "-o", out, "--quiet")
        assert r.rc == 2, f"exit {r.rc} for '{p}'\n" + r.describe()
        assert r.err.count("\n") == 1, r.describe()
        e = re.escape(p)
        assert re.search(rf"^ifem geodesic: error: --path '0,{e}': '{e}'.*(face:F:u:v|u \+ v ≤ 1)",
                         r.err), r.describe()
        assert not out.exists()
        assert not (cli.out / "bad_p.obj.tmp").exists()


# a malformed network line is an error at FILE:LINE saying what was wrong, never skipped
def test_geodesic_network_malformed(cli):
    net, out = cli.out / "net_bad.txt", cli.out / "net_bad.obj"
    for line in ["curve 0 1", "path 0", "loop", "path 0 x", "path 0 face:1:2", "path 0 2930",
                 "path 3 3", "loop 4 5 4", "path 0 face:5856:0.1:0.1"]:
        net.write_text(f"# net\n\npath 0 657\n{line}\n")
        r = cli.run("geodesic", cli.spot, "--network", net, "-o", out, "--quiet")
        assert r.rc == 1, f"exit {r.rc} for '{line}'\n" + r.describe()
        assert r.err.count("\n") == 1, r.describe()
        assert re.search(r"net_bad.txt:4: .*(expected|out of range|same point|not a)", r.err), \
            f"for '{line}':\n" + r.describe()
        assert not out.exists()
        assert not (cli.out / "net_bad.obj.tmp").exists()
    empty = cli.out / "net_empty.txt"
    empty.write_text("# nothing\n\n")
    r = cli.run("geodesic", cli.spot, "--network", empty, "-o", out, "--quiet")
    assert r.rc != 0, r.describe()
    assert grep("net_empty.txt: no curves", r.err), r.describe()
    assert not out.exists()


# fan3: three faces on the edge (2,4); vertex 0 is 3.6511 from that edge's line, vertices 1 and 3
# are 2.5 from it, all above its middle: across the edge, the faces unfolded, 3.6511 + 2.5.
FAN3_ACROSS = 3.6511 + 2.5


# nonmanifold (fan3): two-point paths and --all-from run on the tufted cover (exact shortest
# paths); what needs FlipOut's signposts is refused naming the edge and what does run
def test_geodesic_nonmanifold(cli):
    out = cli.out / "g_nm.txt"
    r = cli.run("geodesic", cli.fan3, "--path", "0,1", "-o", out)
    assert r.rc == 0, r.describe()
    assert grep(r"start won: exact path \(tufted cover\)", r.err), r.describe()
    assert grep("exact distance on the tufted cover", r.out), r.describe()
    assert close(final_length(r.out), FAN3_ACROSS, 1e-11), r.describe()
    (line,) = polylines(out)
    assert close(length3d(line), FAN3_ACROSS, 1e-12)
    assert same_point(line[0], (0, 0, -3.6511)) and same_point(line[-1], (0, -2, 1.5))
    # a face point (the centroid of face 2: 2, 4, 1) to vertex 3, across the edge
    r = cli.run("geodesic", cli.fan3, "--path", "face:2:0.333333333333:0.333333333333,3", "-o",
                out, "--quiet")
    assert r.rc == 0, r.describe()
    centroid_depth = 2.5 / 3  # the centroid's distance from the edge's line
    assert close(final_length(r.out), centroid_depth + 2.5, 1e-9), r.describe()
    lengths = cli.out / "g_nm_all.txt"
    r = cli.run("geodesic", cli.fan3, "--all-from", "0", "-o", lengths, "--quiet")
    assert r.rc == 0, r.describe()
    assert grep("exact distance on the tufted cover", r.out), r.describe()
    d = numbers(lengths)
    assert close(d[1], FAN3_ACROSS, 1e-12) and close(d[3], FAN3_ACROSS, 1e-12)
    assert close(d[2], math.hypot(3, 3.6511), 1e-12) and d[0] == 0
    bad = cli.out / "g_nm.obj"
    for extra, what in ((["--path", "0,1,3"], "a path through more than two points"),
                        (["--path", "0,1,3", "--loop"], "a loop"),
                        (["--path", "0,1,3", "--bezier", "2"], "a Bézier curve")):
        cli.fails_no_partial(
            what + r" needs FlipOut, whose signposts need an edge-manifold, orientable surface, "
            r"and this mesh is not: edge \(2,4\) has 3 incident faces.*two points \(--path A,B\) "
            r"and single-source geodesics \(--all-from S\) run",
            bad, "geodesic", cli.fan3, *extra, "-o", bad, "--quiet")
    r = cli.run("geodesic", cli.fan3, "--network", "/dev/stdin", "-o", bad, "--quiet",
                stdin="path 0 1\npath 3 0\n")
    assert r.rc == 1 and r.err.count("\n") == 1, r.describe()
    assert grep("a network of curves needs FlipOut", r.err), r.describe()
    assert not bad.exists()
    cli.fails_no_partial(r"exceed the memory budget.*no heat-method alternative", bad,
                         "geodesic", cli.fan3, "--path", "0,1", "--memory-budget", "1e-12",
                         "-o", bad, "--quiet")
    cli.fails_no_partial(r"--single-source-flipout.* need signposts.*edge \(2,4\)", lengths.with_suffix(".ply"),
                         "geodesic", cli.fan3, "--all-from", "0", "--single-source-flipout",
                         "-o", lengths.with_suffix(".ply"), "--quiet")


# refused inputs (exit 1, one line, no output): a point cloud (spot's vertices), points on two
# components (two spots); a non-orientable mesh (a Möbius strip made here) takes its two-point
# paths on the tufted cover as a nonmanifold one


def test_geodesic_refused_inputs(cli):
    n = 12
    verts, faces = [], []
    for i in range(n):
        t = 2 * math.pi * i / n
        for s in (-1, 1):
            r = 1 + .3 * s * math.cos(t / 2)
            verts.append((r * math.cos(t), r * math.sin(t), .3 * s * math.sin(t / 2)))
    for i in range(n):
        a = 2 * i + 1
        b, j = a + 1, (i + 1) % n
        c = 2 * j + 1
        d = c + 1
        if i == n - 1:
            c, d = d, c
        faces += [(a, b, d), (a, d, c)]
    moebius = cli.out / "moebius.obj"
    write_obj(moebius, verts, faces)
    mo = cli.out / "g_mo.txt"
    r = cli.run("geodesic", moebius, "--path", "0,5", "-o", mo, "--quiet")
    assert r.rc == 0, r.describe()
    mo_all = cli.out / "g_mo_all.txt"
    assert cli.run("geodesic", moebius, "--all-from", "0", "-o", mo_all, "--quiet").rc == 0
    assert close(final_length(r.out), numbers(mo_all)[5], 1e-11)  # 12 digits printed
    assert close(length3d(polylines(mo)[0]), numbers(mo_all)[5], 1e-12)
    cli.refuse(1, "a loop needs FlipOut.*non-orientable", cli.out / "g_mo.obj", "geodesic",
               moebius, "--path", "0,5,9", "--loop")
    cli.refuse(1, r"geodesic needs a triangle mesh \(the input has no faces",
               cli.out / "g_pc.obj", "geodesic", cli.spot_points(), "--path", "0,1")
    p = obj_vertices(cli.spot)
    f = obj_faces(cli.spot)
    two = cli.out / "two_spots.obj"
    write_obj(two, p + [(x + 5, y, z) for x, y, z in p],
              f + [tuple(i + len(p) for i in t) for t in f])
    cli.refuse(1, "component", cli.out / "g_cc.obj", "geodesic", two, "--path", "0,3000")
    r = cli.run("geodesic", two, "--network", "/dev/stdin", "-o", cli.out / "g_cc.txt",
                "--quiet", stdin="path 0 657\npath 10 4000\n")
    assert r.rc == 1, r.describe()
    assert r.err.count("\n") == 1, r.describe()
    assert re.search("component", r.err), r.describe()
    assert not (cli.out / "g_cc.txt").exists()
    assert not (cli.out / "g_cc.txt.tmp").exists()



def test_default_lengths_are_the_inputs_own(cli):
    """geodesic measures the input's own lengths by default (docs/decisions.md D-350): a unit
    square with a vertex 1e-9 above its bottom side (a sliver below the other commands' 1e-5
    margin, which lengthens every edge) has the diagonal sqrt(2) to round-off, in --path and
    --all-from; --mollify 1e-5 is honoured (longer). Four coincident copies of a point joined
    by zero-area faces are still crossed: each 2 from the apex."""
    mesh = cli.out / "sliver_square.obj"
    write_obj(mesh, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 1e-9, 0)],
              [(1, 2, 5), (1, 5, 4), (5, 2, 3), (5, 3, 4)])
    out = cli.out / "diag.txt"

    def length(*extra):
        r = cli.ok("geodesic", mesh, "--path", "0,2", "-o", out, *extra)
        return float(re.search(r"length [0-9.e+-]+ -> ([0-9.e+-]+)", r.out).group(1))

    assert abs(length() - math.sqrt(2)) <= 1e-11
    assert length("--mollify", "1e-5") - math.sqrt(2) > 1e-8
    cli.ok("geodesic", mesh, "--all-from", 0, "-o", out, "--quiet")
    assert abs(numbers(out)[2] - math.sqrt(2)) <= 1e-11
    fused = cli.out / "coincident_center.obj"
    write_obj(fused, [(0, 0, 0), (3, 0, 0), (1.5, 3, 0)] + [(1.5, 1, 0)] * 4,
              [(1, 2, 4), (2, 5, 4), (1, 4, 6), (4, 5, 7), (5, 6, 7), (6, 4, 7), (2, 3, 5),
               (1, 6, 3), (6, 5, 3)])
    for flipout in ([], ["--single-source-flipout"]):
        cli.ok("geodesic", fused, "--all-from", 2, "-o", out, "--quiet", *flipout)
        assert all(abs(x - 2.0) <= 1e-11 for x in numbers(out)[3:]), (flipout, numbers(out))

def test_isolated_vertex_is_refused_by_name(cli):
    """A curve through a vertex that no face uses: refused up front naming it, from either end
    (it used to fail in the start guide's heat distance, "sources[0] = 4 is not referenced",
    or as "not reachable"); single-source from it too (it wrote inf everywhere)."""
    mesh = cli.out / "square_and_lone_vertex.obj"
    write_obj(mesh, [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (5, 5, 5)],
              [(1, 2, 3), (1, 3, 4)])
    for path in ("0,4", "4,0", "0,2,4"):
        cli.refuse(1, r"--path: vertex 4 is used by no face \(an isolated vertex, not on the "
                      r"surface\)$", cli.out / "p.txt", "geodesic", mesh, "--path", path)
    net = cli.out / "net.txt"
    net.write_text("path 0 2\npath 2 4\n")
    cli.refuse(1, r"net.txt:2: vertex 4 is used by no face", cli.out / "p.obj", "geodesic", mesh,
               "--network", net)
    # single-source from it: refused as `distance --exact` refuses it (not a file of inf)
    cli.refuse(1, r"source = 4: vertex used by no face \(an isolated vertex", cli.out / "s.txt",
               "geodesic", mesh, "--all-from", 4)


# FlipOut's geodesic from rocketship vertex 15838 to 0 is held 3.5e-3 longer than the exact
# distance (a saddle vertex; docs/decisions.md D-375): the exact path is written instead
def test_pair_path_is_never_longer_than_exact(cli, shared_data):
    mesh = shared_data / "meshes" / "rocketship.ply"
    exact = numbers(shared_data / "reference" / "rocketship.src0.exact.txt")
    out = cli.out / "g_rocket.txt"
    r = cli.run("geodesic", mesh, "--path", "15838,0", "--mollify", "0", "-o", out)
    assert r.rc == 0, r.describe()
    assert grep(r"start won: exact path \(FlipOut's geodesic from .* was 3\.\d+e-03 longer\)",
                r.err), r.describe()
    assert final_length(r.out) <= exact[15838] * (1 + 1e-9), r.describe()
    assert close(final_length(r.out), exact[15838], 1e-9)
    assert close(length3d(polylines(out)[0]), exact[15838], 1e-9)
