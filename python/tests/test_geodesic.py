"""geodesic_path / geodesic_network / bezier_curve / single_source_geodesics: against the CLI's
output files (`ifem geodesic`, same mesh and points, 1e-12), against known truth on a flat mesh
(geodesics are straight segments, Bézier curves converge to the planar Bézier curve), and bad
input."""

import re
import threading

import numpy as np
import pytest

import ifem
from conftest import (flat_grid, read_obj_polylines, read_txt, run_cli, run_cli_logged,
                      test_data)

SPOT = test_data("spot.obj")


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(SPOT)


def read_txt_polylines(path):
    """The CLI's .txt curves: 'x y z' lines, an empty line between curves."""
    blocks = path.read_text().strip().split("\n\n")
    return [np.array([[float(w) for w in line.split()] for line in b.splitlines()])
            for b in blocks]


def cli_lengths(stdout):
    """Per curve (initial, final) from 'curve k (...): length A -> B' lines, and the FlipOut
    line's flips, iterations and stop reason."""
    lengths = [(float(a), float(b)) for a, b in
               re.findall(r"length ([0-9.e+-]+) -> ([0-9.e+-]+)", stdout)]
    m = re.search(r"FlipOut: (\d+) flips, (\d+) iterations, stopped: ([a-z ]+)", stdout)
    return lengths, (int(m.group(1)), int(m.group(2)), m.group(3).strip())


def assert_report_matches(report, stdout, lengths):
    cli, (flips, iterations, stopped) = cli_lengths(stdout)
    assert (report.flips, report.iterations, report.stopped_by) == (flips, iterations, stopped)
    assert report.converged == (stopped == "converged")
    for (a, b), (ia, fb) in zip(cli, lengths):  # the CLI prints 12 significant digits
        assert abs(ia - a) <= 1e-11 * a and abs(fb - b) <= 1e-11 * b


def polyline_length(P):
    return np.linalg.norm(np.diff(P, axis=0), axis=1).sum()


# ---- against the CLI -------------------------------------------------------------------------

def test_path_through_vertices_and_a_face_point_matches_cli(spot, tmp_path):
    V, F = spot
    out = run_cli("geodesic", SPOT, "--path", "0,face:12:0.3:0.25,1200", "-o",
                  tmp_path / "p.txt", "--quiet")
    c = ifem.geodesic_path(V, F, [0, (12, 1 - 0.3 - 0.25, 0.3, 0.25), 1200])
    (P,) = read_txt_polylines(tmp_path / "p.txt")
    assert c.polyline.shape == P.shape and c.polyline.dtype == np.float64
    assert abs(c.polyline - P).max() <= 1e-12
    assert_report_matches(c.report, out, [(c.initial_length, c.length)])
    assert c.report.converged and c.length < c.initial_length and not c.closed
    # the polyline's 3D length is the intrinsic length (spot needs no mollification)
    assert abs(polyline_length(c.polyline) - c.length) <= 1e-9 * c.length
    # it starts and ends at the given points, and passes through the face point
    assert np.array_equal(c.points[[0, 2]], V[[0, 1200]])
    assert np.allclose(c.points[1], 0.45 * V[F[12, 0]] + 0.3 * V[F[12, 1]] + 0.25 * V[F[12, 2]],
                       atol=1e-14)
    assert np.array_equal(c.polyline[0], V[0]) and np.array_equal(c.polyline[-1], V[1200])
    assert np.abs(c.polyline - c.points[1]).sum(axis=1).min() <= 1e-12


# start: the CLI's --start; from spot's vertex 2222 to 0 the shortest edge path wraps a vertex the
# other way than the shortest geodesic: "dijkstra" ends 0.37% above the exact distance
# (tests/data/reference/spot.src0.exact.txt), the default ("best") on it
def test_start_paths_match_cli_and_the_exact_distance(spot, tmp_path):
    V, F = spot
    exact = float(np.loadtxt(test_data("reference/spot.src0.exact.txt"))[2222])
    lengths = {}
    for start in ["dijkstra", "best"]:
        out, log = run_cli_logged("geodesic", SPOT, "--path", "2222,0", "--start", start, "-o",
                                  tmp_path / f"{start}.txt")
        c = ifem.geodesic(V, F, [2222, 0], start=start)
        (P,) = read_txt_polylines(tmp_path / f"{start}.txt")
        assert c.polyline.shape == P.shape and abs(c.polyline - P).max() <= 1e-12
        assert_report_matches(c.report, out, [(c.initial_length, c.length)])
        lengths[start] = c.length
        # which start won: the library's GeodesicCurves::start_won, the CLI's "start won:" line
        won = re.findall(r"^ifem: start won: (.*)$", log, re.M)
        assert won == ([c.start_won] if c.start_won else []), (won, c.start_won)
        assert (c.start_won == "") == (start == "dijkstra"), c.start_won
    assert re.fullmatch(r"shortest edge path|(exact geodesic|descent) to (b|a, reversed), "
                        r"(shorter|left|right) side", ifem.geodesic(V, F, [2222, 0]).start_won)
    # a network (several curves shortened together) starts from shortest edge paths
    assert [c.start_won for c in ifem.geodesic_network(V, F, [[0, 500], [10, 700]]).curves] == \
        ["", ""]
    assert abs(lengths["best"] - exact) <= 1e-6 * exact
    assert lengths["dijkstra"] > exact * (1 + 1e-3)
    with pytest.raises(ifem.InvalidInput, match="start = 'fast'"):
        ifem.geodesic_path(V, F, [2222, 0], start="fast")


@pytest.mark.parametrize("pin", [False, True])
def test_loop_matches_cli(spot, tmp_path, pin):
    V, F = spot
    args = ["--pin"] if pin else []
    out = run_cli("geodesic", SPOT, "--path", "1392,1382,323", "--loop", *args, "-o",
                  tmp_path / "l.obj", "--quiet")
    c = ifem.geodesic_path(V, F, [1392, 1382, 323], loop=True, pin=pin)
    (P,) = read_obj_polylines(tmp_path / "l.obj")
    assert c.closed and not c.collapsed
    assert c.polyline.shape == P.shape and abs(c.polyline - P).max() <= 1e-12
    assert np.array_equal(c.polyline[0], c.polyline[-1])  # a loop repeats its first point
    assert_report_matches(c.report, out, [(c.initial_length, c.length)])


def test_bezier_matches_cli(spot, tmp_path):
    V, F = spot
    out = run_cli("geodesic", SPOT, "--path", "0,500,1200,2000", "--bezier", 3, "-o",
                  tmp_path / "b.txt", "--quiet")
    b = ifem.bezier_curve(V, F, [0, 500, 1200, 2000], rounds=3)
    (P,) = read_txt_polylines(tmp_path / "b.txt")
    assert b.polyline.shape == P.shape and abs(b.polyline - P).max() <= 1e-12
    assert_report_matches(b.report, out, [(b.initial_length, b.length)])
    m = re.search(r"Bézier: (\d+) control points after 3 rounds .*, (\d+) midpoints", out)
    assert (b.control_points, b.midpoints) == (int(m.group(1)), int(m.group(2)))
    assert b.control_points == 3 * 2 ** 3 + 1 and b.rounds == 3
    assert isinstance(b, ifem.GeodesicCurve)
    # rounds=0: the geodesic control polygon, i.e. the pinned path through the points
    b0 = ifem.bezier_curve(V, F, [0, 500, 1200, 2000], rounds=0)
    path = ifem.geodesic_path(V, F, [0, 500, 1200, 2000])
    assert abs(b0.length - path.length) <= 1e-12 * path.length


def test_network_matches_cli(spot, tmp_path):
    V, F = spot
    net_file = tmp_path / "net.txt"
    net_file.write_text("# two paths and a loop\npath 0 500 1200\n\n"
                        "path 100 face:40:0.2:0.2 1500\nloop 1392 1382 323  # around the body\n")
    out = run_cli("geodesic", SPOT, "--network", net_file, "-o", tmp_path / "n.txt", "--quiet")
    cli = read_txt_polylines(tmp_path / "n.txt")
    net = ifem.geodesic_network(V, F, [[0, 500, 1200], [100, (40, 1 - 0.2 - 0.2, 0.2, 0.2), 1500],
                                       {"points": [1392, 1382, 323], "loop": True}])
    assert [c.closed for c in net.curves] == [False, False, True]
    assert len(net.polylines) == len(cli) == 3
    for mine, theirs in zip(net.polylines, cli):
        assert mine.shape == theirs.shape and abs(mine - theirs).max() <= 1e-12
    assert_report_matches(net.report, out, [(c.initial_length, c.length) for c in net.curves])
    assert abs(net.lengths.sum() - net.report.final_length) <= 1e-12 * net.report.final_length
    # the network file itself gives the same curves
    from_file = ifem.geodesic_network(V, F, net_file)
    for a, b in zip(from_file.polylines, net.polylines):
        assert np.array_equal(a, b)


def test_single_source_matches_cli(spot, tmp_path):
    V, F = spot
    run_cli("geodesic", SPOT, "--all-from", 7, "-o", tmp_path / "g.txt", "--quiet")
    g = ifem.single_source_geodesics(V, F, 7)
    d = read_txt(tmp_path / "g.txt")
    assert g.length.shape == (len(V),) and g.paths is None
    assert abs(g.length - d).max() <= 1e-12 * d.max()
    assert g.length[7] == 0 and np.isfinite(g.length).all()
    # a geodesic is never shorter than the straight line, never longer than the edge path
    assert (g.length >= np.linalg.norm(V - V[7], axis=1) * (1 - 1e-12)).all()
    # with paths: each one runs from the source to its vertex and is as long as its length
    gp = ifem.single_source_geodesics(V, F, 7, return_paths=True)
    assert np.array_equal(gp.length, g.length) and len(gp.paths) == len(V)
    assert np.array_equal(gp.paths[7], V[[7]])
    for v in range(0, len(V), 97):
        P = gp.paths[v]
        if v == 7:
            continue
        assert np.array_equal(P[0], V[7]) and np.array_equal(P[-1], V[v])
        assert abs(polyline_length(P) - g.length[v]) <= 1e-9 * g.length[v]


def test_single_source_exact_by_default_flipout_on_request(spot):
    V, F = spot
    g = ifem.single_source_geodesics(V, F, 7, return_paths=True)
    assert g.exact and g.windows > 0 and g.flips == 0
    f = ifem.single_source_geodesics(V, F, 7, single_source_flipout=True)
    assert not f.exact and f.windows == 0 and f.flips > 0
    # the exact geodesics are the shortest: FlipOut's are never shorter, equal on most vertices
    assert (f.length >= g.length * (1 - 1e-9)).all()
    assert np.mean(np.abs(f.length - g.length) <= 1e-9 * g.length.max()) >= 0.9
    # the exact paths run on the surface: never shorter than their chords, as long as the length
    for v in range(1, len(V), 61):
        P = g.paths[v]
        assert np.array_equal(P[0], V[7]) and np.allclose(P[-1], V[v], atol=1e-12)
        assert abs(polyline_length(P) - g.length[v]) <= 1e-9 * g.length[v]
    same = ifem.geodesic(V, F, all_from=7, single_source_flipout=True)
    assert np.array_equal(same.length, f.length)
    with pytest.raises(ifem.InvalidInput, match="single_source_flipout applies to all_from"):
        ifem.geodesic(V, F, points=[0, 1], single_source_flipout=True)


def test_single_source_unreachable_is_inf(tmp_path):
    # two separate squares: the second one is unreachable from the first
    V, F = flat_grid(4)
    V2 = np.r_[V, V + [2.0, 0, 0]]
    F2 = np.r_[F, F + len(V)]
    g = ifem.single_source_geodesics(V2, F2, 0)
    assert np.isfinite(g.length[:len(V)]).all() and np.isinf(g.length[len(V):]).all()
    mesh = tmp_path / "two.obj"
    mesh.write_text("".join(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V2) +
                    "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F2))
    run_cli("geodesic", mesh, "--all-from", 0, "-o", tmp_path / "g.txt", "--quiet")
    assert np.array_equal(read_txt(tmp_path / "g.txt"), g.length)  # inf where the CLI says inf
    with pytest.raises(ifem.InvalidInput, match="different connected components|component"):
        ifem.geodesic_path(V2, F2, [0, len(V) + 3])


# ---- known truth on a flat mesh ------------------------------------------------------------

@pytest.mark.parametrize("points", [[0, 16 * 17 + 16], [3 + 2 * 17, 13 + 12 * 17],
                                    [1 + 3 * 17, (40, 0.2, 0.3, 0.5)]])
def test_flat_geodesic_is_the_straight_segment(points):
    V, F = flat_grid(16)
    c = ifem.geodesic_path(V, F, points)
    P = c.polyline
    chord = P[-1] - P[0]
    assert c.report.converged
    assert abs(c.length - np.linalg.norm(chord)) <= 1e-9
    assert abs(polyline_length(P) - np.linalg.norm(chord)) <= 1e-9
    # every traced point on the segment (collinear, in order)
    u = chord / np.linalg.norm(chord)
    assert np.linalg.norm(np.cross(P - P[0], u), axis=1).max() <= 1e-12
    assert (np.diff((P - P[0]) @ u) > -1e-15).all()
    assert c.length < c.initial_length  # the edge path zigzags on the jittered grid


def test_default_lengths_are_the_inputs_own():
    """A sliver below the other commands' 1e-5 margin: geodesics default to the input's own
    lengths (D-350), the unit square's diagonal is sqrt(2); mollify=1e-5 is honoured (longer)."""
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 1e-9, 0]], float)
    F = np.array([[0, 1, 4], [0, 4, 3], [4, 1, 2], [4, 2, 3]])
    assert abs(ifem.geodesic_path(V, F, [0, 2]).length - np.sqrt(2)) <= 1e-11
    assert abs(ifem.single_source_geodesics(V, F, 0).length[2] - np.sqrt(2)) <= 1e-11
    assert ifem.geodesic_path(V, F, [0, 2], mollify=1e-5).length - np.sqrt(2) > 1e-8


def test_flat_bezier_converges_to_the_planar_bezier_curve():
    V, F = flat_grid(16)
    ctrl = [1 + 1 * 17, 8 + 15 * 17, 15 + 1 * 17]
    P0, P1, P2 = V[ctrl]
    t = np.linspace(0, 1, 20001)[:, None]
    exact = (1 - t) ** 2 * P0 + 2 * t * (1 - t) * P1 + t ** 2 * P2
    errors = []
    for rounds in (2, 4, 6):
        b = ifem.bezier_curve(V, F, ctrl, rounds=rounds)
        assert b.control_points == 2 * 2 ** rounds + 1
        assert np.array_equal(b.polyline[0], P0) and np.array_equal(b.polyline[-1], P2)
        errors.append(max(np.linalg.norm(exact - p, axis=1).min() for p in b.polyline))
    # de Casteljau: the control polygon approaches the curve by 4× per round
    assert errors[0] > 8 * errors[1] > 64 * errors[2] and errors[2] < 5e-4


def test_network_curves_do_not_cross():
    V, F = flat_grid(12)
    vid = lambda i, j: j * 13 + i  # noqa: E731
    # two diagonals of the square must meet at a vertex (they cannot cross inside a face)
    net = ifem.geodesic_network(V, F, [[vid(0, 0), vid(12, 12)], [vid(0, 12), vid(12, 0)]])
    a, b = net.polylines
    assert any((np.abs(b - p).sum(axis=1) <= 1e-12).any() for p in a)


def test_loop_on_a_flat_disk_collapses():
    V, F = flat_grid(8)
    c = ifem.geodesic_path(V, F, [2 + 2 * 9, 6 + 2 * 9, 4 + 6 * 9], loop=True)
    assert c.closed and c.collapsed and c.length <= 1e-12


def test_gil_is_released_and_calls_are_independent(spot):
    V, F = spot
    want = ifem.single_source_geodesics(V, F, 3).length
    got = [None, None]

    def run(k):
        got[k] = ifem.single_source_geodesics(V, F, 3).length

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(g, want) for g in got)


# ---- bad input ---------------------------------------------------------------------------

def bad_calls(V, F):
    n = len(V)
    return [
        (lambda: ifem.geodesic_path(V, F, [0, n]), ifem.InvalidInput,
         rf"points\[1\] = {n}: vertex out of range \[0, {n}\)"),
        (lambda: ifem.geodesic_path(V, F, [-1, 3]), ifem.InvalidInput,
         r"points\[0\] = -1: vertex out of range"),
        (lambda: ifem.geodesic_path(V, F, [5]), ifem.InvalidInput,
         "points needs at least 2 points, got 1"),
        (lambda: ifem.geodesic_path(V, F, [5, 5]), ifem.InvalidInput,
         r"points\[0\] and points\[1\] are the same point"),
        (lambda: ifem.geodesic_path(V, F, [5, 9, 5], loop=True), ifem.InvalidInput,
         "a loop closes by itself"),
        (lambda: ifem.geodesic_path(V, F, [0, (len(F), 1, 0, 0)]), ifem.InvalidInput,
         rf"points\[1\]: face {len(F)} out of range"),
        (lambda: ifem.geodesic_path(V, F, [0, (3, 0.5, 0.5, 0.5)]), ifem.InvalidInput,
         "must sum to 1"),
        (lambda: ifem.geodesic_path(V, F, [0, (3, np.nan, 0.5, 0.5)]), ifem.InvalidInput,
         "b0 = nan must be finite"),
        (lambda: ifem.geodesic_path(V, F, [0, (3, -0.1, 0.6, 0.5)]), ifem.InvalidInput,
         "must be finite and ≥ 0"),
        (lambda: ifem.geodesic_path(V, F, [0, 2.5]), ifem.InvalidInput,
         r"points\[1\] must be a vertex id"),
        (lambda: ifem.geodesic_path(V, F, "0,1"), ifem.InvalidInput,
         "points must be a sequence of points"),
        (lambda: ifem.geodesic_path(V, F, [0, 100], pin=True), ifem.InvalidInput,
         "pin=True applies to loops"),
        (lambda: ifem.geodesic_path(V, F, [0, 1], mollify=np.nan), ifem.InvalidInput,
         "mollify must be in"),
        (lambda: ifem.bezier_curve(V, F, [0, 100, 200], rounds=17), ifem.InvalidInput,
         r"rounds must be in \[0, 16\]"),
        (lambda: ifem.bezier_curve(V, F, [0, 100, 200], rounds=-1), ifem.InvalidInput,
         r"rounds must be in \[0, 16\]"),
        (lambda: ifem.bezier_curve(V, F, [0, 100, 200], rounds=2.5), ifem.InvalidInput,
         "rounds must be an integer"),
        (lambda: ifem.bezier_curve(V, F, [0, n + 4], rounds=2), ifem.InvalidInput,
         r"control_points\[1\] = "),
        (lambda: ifem.single_source_geodesics(V, F, n), ifem.InvalidInput,
         rf"source = {n}: vertex out of range"),
        (lambda: ifem.single_source_geodesics(V, F, 1.0), ifem.InvalidInput,
         "source must be a vertex id"),
        (lambda: ifem.geodesic_network(V, F, [[0, 100], [7]]), ifem.InvalidInput,
         r"curves\[1\] needs at least 2 points"),
        (lambda: ifem.geodesic_network(V, F, [[0, 100], [7, n]]), ifem.InvalidInput,
         r"curves\[1\]\[1\] = "),
        (lambda: ifem.geodesic_network(V, F, [[0, 100], {"points": [1, 2], "closed": True}]),
         ifem.InvalidInput, r"curves\[1\] must be a point list or a dict"),
        (lambda: ifem.geodesic_network(V, F, []), ifem.InvalidInput, "curves is empty"),
        (lambda: ifem.geodesic_path(V, np.zeros((0, 3), int), [0, 1]), ifem.InvalidInput,
         "F has no faces"),
        (lambda: ifem.geodesic_path(np.zeros((3, 3)), [[0, 1, 2]], [0, 1]), ifem.InvalidInput,
         "zero total area"),
    ]


def test_bad_input_raises_with_a_clear_message(spot):
    for call, exc, message in bad_calls(*spot):
        with pytest.raises(exc, match=message):
            call()


def test_isolated_vertex_is_refused_by_name():
    # as the CLI (the recipe's check_curves): a curve point no face uses, from either end
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [5, 5, 5]], float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    for points in ([0, 4], [4, 0]):
        with pytest.raises(ifem.InvalidInput, match="vertex 4 is used by no face"):
            ifem.geodesic_path(V, F, points)
    with pytest.raises(ifem.InvalidInput, match="source = 4: vertex used by no face"):
        ifem.single_source_geodesics(V, F, 4)


def test_bad_network_file(spot, tmp_path):
    V, F = spot
    bad = tmp_path / "bad.txt"
    bad.write_text("path 0 10\ncurve 1 2\n")
    with pytest.raises(ifem.IoError, match=r"bad.txt:2: expected 'path P0 P1 \.\.\.'"):
        ifem.geodesic_network(V, F, bad)
    bad.write_text("path 0 face:1:x:0\n")
    with pytest.raises(ifem.IoError, match=r"bad.txt:1: 'face:1:x:0' is not a point"):
        ifem.geodesic_network(V, F, bad)
    with pytest.raises(ifem.IoError, match="cannot open"):
        ifem.geodesic_network(V, F, tmp_path / "missing.txt")


def test_nonmanifold_mesh_two_points_and_single_source_on_the_tufted_cover():
    """Three triangles on the edge 0–1: a path between two points and single-source geodesics
    are the exact shortest paths on the tufted cover (across the edge: the two faces unfolded);
    what needs FlipOut's signposts is refused saying what does run."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0.2], [0.5, 0.1, 1.0]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    across = 1 + np.hypot(1, 0.2)  # 2 and 3 are 1 and √1.04 from the edge, above x = 0.5
    c = ifem.geodesic_path(V, F, [2, 3])
    assert c.start_won == "exact path (tufted cover)"
    assert c.length == pytest.approx(across, rel=1e-12)
    assert polyline_length(c.polyline) == pytest.approx(across, rel=1e-12)
    assert np.allclose(c.polyline[0], V[2], atol=1e-12) and np.allclose(c.polyline[-1], V[3],
                                                                         atol=1e-12)
    # a face point (the centroid of face 1) to vertex 2
    f = ifem.geodesic_path(V, F, [(1, 1 / 3, 1 / 3, 1 / 3), 2])
    assert f.length == pytest.approx(1 + np.hypot(1, 0.2) / 3, rel=1e-12)
    g = ifem.single_source_geodesics(V, F, 2, return_paths=True)
    assert g.exact and g.tufted_cover
    assert g.length[3] == pytest.approx(across, rel=1e-12)
    assert g.length[0] == pytest.approx(np.hypot(0.5, 1), rel=1e-12)
    assert polyline_length(g.paths[3]) == pytest.approx(across, rel=1e-12)
    assert np.allclose(g.paths[3][0], V[2], atol=1e-12)
    with pytest.raises(ifem.NonManifoldInput,
                       match=r"a path through more than two points needs FlipOut.*edge \(0,1\)"
                             r".*--path A,B.*--all-from"):
        ifem.geodesic_path(V, F, [2, 3, 4])
    with pytest.raises(ifem.NonManifoldInput, match="a loop needs FlipOut"):
        ifem.geodesic_path(V, F, [2, 3, 4], loop=True)
    with pytest.raises(ifem.NonManifoldInput, match="a network of curves needs FlipOut"):
        ifem.geodesic_network(V, F, [[2, 3], [3, 4]])
    with pytest.raises(ifem.NonManifoldInput, match="single_source_flipout.*need signposts"):
        ifem.single_source_geodesics(V, F, 2, single_source_flipout=True)


def test_nonmanifold_path_matches_cli(tmp_path):
    V, F = ifem.read_mesh(test_data("fan3.obj"))
    out = tmp_path / "p.txt"
    stdout = run_cli("geodesic", test_data("fan3.obj"), "--path", "0,1", "-o", out)
    c = ifem.geodesic(V, F, [0, 1])
    (line,) = read_txt_polylines(out)
    assert np.allclose(c.polyline, line, rtol=0, atol=1e-12)
    assert abs(c.length - float(re.search(r"-> ([0-9.e+-]+)", stdout).group(1))) <= 1e-11
    lengths = tmp_path / "all.txt"
    run_cli("geodesic", test_data("fan3.obj"), "--all-from", "0", "-o", lengths)
    g = ifem.geodesic(V, F, all_from=0)
    assert np.allclose(g.length, read_txt(lengths), rtol=1e-15, atol=0)


def test_network_file_is_read_by_the_library(spot, tmp_path):
    """One reader for network files (the CLI's): a face point with u + v > 1 is refused at
    FILE:line (Python used to clamp it), and face points come back as (F, 1 - u - v, u, v)."""
    V, F = spot
    net = tmp_path / "net.txt"
    net.write_text("# two curves\npath 0 face:40:0.25:0.5 1500\n\nloop 10 200 350\n")
    assert ifem.read_network(net) == [{"points": [0, (40, 0.25, 0.25, 0.5), 1500], "loop": False},
                                      {"points": [10, 200, 350], "loop": True}]
    net.write_text("path 0 1500\npath 0 face:40:0.7:0.7\n")
    with pytest.raises(ifem.IoError, match=r"net.txt:2: 'face:40:0.7:0.7': .*u \+ v ≤ 1"):
        ifem.read_network(net)
    with pytest.raises(ifem.IoError, match=r"net.txt:2: "):
        ifem.geodesic(V, F, network=net)


def test_geodesic_modes_are_keywords(spot):
    V, F = spot
    path = ifem.geodesic(V, F, points=[0, 500, 1200])
    assert path.length == ifem.geodesic_path(V, F, [0, 500, 1200]).length
    loop = ifem.geodesic(V, F, points=[0, 500, 1200], loop=True, pin=True)
    assert loop.closed and loop.length == pytest.approx(
        ifem.geodesic_path(V, F, [0, 500, 1200], loop=True, pin=True).length, abs=0)
    b = ifem.geodesic(V, F, points=[0, 500, 1200], bezier=2)
    assert isinstance(b, ifem.BezierCurve) and b.rounds == 2
    ss = ifem.geodesic(V, F, all_from=7)
    assert ss.length[7] == 0 and np.array_equal(ss.length,
                                                ifem.single_source_geodesics(V, F, 7).length)
    for kwargs, message in [({}, "exactly one of points, network, all_from"),
                            ({"points": [0, 1], "all_from": 3}, "exactly one"),
                            ({"all_from": 3, "bezier": 2}, "bezier takes points"),
                            ({"network": [[0, 1]], "loop": True}, "loop closes"),
                            ({"points": [0, 1], "return_paths": True}, "return_paths applies")]:
        with pytest.raises(ifem.InvalidInput, match=message):
            ifem.geodesic(V, F, **kwargs)


# issue 30: a network stopped at FlipOut's iteration cap is not geodesic: an error stating what
# was reached, unless accepted; a Bézier curve finer than the mesh or over its memory budget is
# refused before any work, with the rounds that fit (which complete)
def test_iteration_cap_and_bezier_budget(spot):
    V, F = spot
    net = [[0, 500, 1000], [10, 700, 1400], {"points": [20, 900, 1800], "loop": True}]
    with pytest.raises(ifem.InvalidInput, match=r"iteration cap \(3 reroutes.*accept"):
        ifem.geodesic_network(V, F, net, max_iterations=3)
    partial = ifem.geodesic(V, F, network=net, max_iterations=3, accept_partial=True)
    assert partial.report.stopped_by == "iteration cap"
    assert ifem.geodesic_network(V, F, net).report.stopped_by != "iteration cap"
    with pytest.raises(ifem.InvalidInput, match=r"control_points: a Bézier curve of degree 3 "
                                                r"with 16 rounds .*Use at most 8 rounds"):
        ifem.bezier_curve(V, F, [0, 500, 1000, 1500], rounds=16)
    assert ifem.bezier_curve(V, F, [0, 500, 1000, 1500], rounds=8).midpoints > 0
    with pytest.raises(ifem.InvalidInput, match="above the memory budget of 0.001 GB"):
        ifem.geodesic(V, F, [0, 500, 1000, 1500], bezier=4, memory_budget=0.001)
