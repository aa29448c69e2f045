"""curve_poisson / curve_distance / Curve / read_curves: against the CLI's output files (`ifem
poisson --curves`, `ifem distance --curves`, `--curves-out`; same mesh and curves file, 1e-12),
against known truth on a flat square (linear data reproduced exactly, slits separating the
sides, distance to a straight curve), and bad input."""

import functools

import numpy as np
import pytest

import conftest
import ifem
from conftest import read_obj_polylines, read_txt, run_cli, test_data

# the curves tests' square keeps its left and right sides' vertices in place
flat_grid = functools.partial(conftest.flat_grid, slide_left_right=False)

SPOT = test_data("spot.obj")
# a Bézier curve from 0 to 1, a slit (0.2 on its left, 0.8 on its right) and a loop at 0.5
SPOT_CURVES = ("bezier=3 0 1 : 0 500 1200\n"
               "slit 0.2 0.8 100 900 1500  # a cut\n"
               "\n"
               "closed 0.5 1392 1382 323\n")


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(SPOT)


@pytest.fixture
def spot_curves(tmp_path):
    p = tmp_path / "curves.txt"
    p.write_text(SPOT_CURVES)
    return p


def row(n, j):
    """Ends of the straight curve across the square along row j."""
    return [j * (n + 1), j * (n + 1) + n]


def write_obj(path, V, F):
    path.write_text("".join(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V) +
                    "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F))


# ---- against the CLI -------------------------------------------------------------------------

@pytest.mark.parametrize("refine", [False, True])
def test_poisson_matches_cli(spot, spot_curves, tmp_path, refine):
    V, F = spot
    args = ["--refine"] if refine else []
    run_cli("poisson", SPOT, "--curves", spot_curves, *args, "-o", tmp_path / "u.txt",
            "--curves-out", tmp_path / "c.obj", "--quiet")
    u, lines, info = ifem.curve_poisson(V, F, spot_curves, refine=refine, return_polylines=True,
                                        return_info=True)
    want = read_txt(tmp_path / "u.txt")
    assert u.shape == (len(V),) and abs(u - want).max() <= 1e-12
    cli_lines = read_obj_polylines(tmp_path / "c.obj")
    assert len(lines) == len(cli_lines) == 3
    for mine, theirs in zip(lines, cli_lines):
        assert mine.shape == theirs.shape and abs(mine - theirs).max() <= 1e-12
    assert abs(lines[2][0] - lines[2][-1]).max() <= 1e-12  # a loop ends at its first point
    # maximum principle: u within the curves' values; the slit's sides are cut apart
    assert u.min() >= -1e-9 and u.max() <= 1 + 1e-9
    assert info["slit_copies"] > 0 and info["refined"] == refine
    assert info["dirichlet_vertices"] > 0 and info["negative_weights_elsewhere"] == 0
    # the same from Curve objects, and from what read_curves makes of the file
    curves = [ifem.Curve([0, 500, 1200], [0, 1], bezier=3),
              ifem.Curve([100, 900, 1500], left=0.2, right=0.8),
              ifem.Curve([1392, 1382, 323], 0.5, closed=True)]
    assert ifem.read_curves(spot_curves) == curves
    assert np.array_equal(ifem.curve_poisson(V, F, curves, refine=refine), u)


def test_poisson_rhs_dirichlet_screening_match_cli(spot, tmp_path):
    V, F = spot
    curves = [ifem.Curve([0, 500, 1200], [0.0, 0.3, 1.0]), ifem.Curve([100, 900], 2.0)]
    ifem.write_curves(tmp_path / "c.txt", curves)
    f = np.sin(3 * V[:, 0]) + V[:, 2]
    np.savetxt(tmp_path / "f.txt", f, fmt="%.17g")
    (tmp_path / "bc.txt").write_text("2000 -1\n2500 0.25\n")
    run_cli("poisson", SPOT, "--curves", tmp_path / "c.txt", "--rhs", tmp_path / "f.txt",
            "--dirichlet", tmp_path / "bc.txt", "--screening", 2, "-o", tmp_path / "u.txt",
            "--quiet")
    u = ifem.curve_poisson(V, F, curves, rhs=f, dirichlet={2000: -1, 2500: 0.25}, screening=2)
    assert abs(u - read_txt(tmp_path / "u.txt")).max() <= 1e-12
    assert u[2000] == -1 and u[2500] == 0.25
    u2 = ifem.curve_poisson(V, F, curves, rhs=f, dirichlet=([2000, 2500], [-1, 0.25]),
                            screening=2)
    assert np.array_equal(u, u2)


@pytest.mark.parametrize("refine", [False, True])
def test_distance_matches_cli(spot, spot_curves, tmp_path, refine):
    V, F = spot
    args = ["--refine"] if refine else []
    run_cli("distance", SPOT, "--curves", spot_curves, *args, "-o", tmp_path / "d.txt",
            "--quiet")
    d, info = ifem.curve_distance(V, F, spot_curves, refine=refine, return_info=True)
    assert abs(d - read_txt(tmp_path / "d.txt")).max() <= 1e-12
    assert info["stages"] >= 1
    for v in (0, 1200, 100, 900, 1500, 1392, 1382, 323):  # given vertices lie on the curves
        assert d[v] == 0


def test_distance_settings_match_cli(spot, spot_curves, tmp_path):
    V, F = spot
    run_cli("distance", SPOT, "--curves", spot_curves, "--time-factor", 3,
            "--correction-steps", 2, "-o", tmp_path / "d.txt", "--quiet")
    d = ifem.curve_distance(V, F, spot_curves, time_factor=3, correction_steps=2)
    assert abs(d - read_txt(tmp_path / "d.txt")).max() <= 1e-12
    assert abs(d - ifem.curve_distance(V, F, spot_curves)).max() > 1e-6  # the settings matter


# FlipOut's cap on the curves (the CLI's --max-iterations): reaching it is an error stating what
# was reached unless accept_partial (--accept-partial), and then the result is the CLI's
def test_iteration_cap_matches_cli(spot, tmp_path):
    V, F = spot
    curves = [ifem.Curve([0, 1500], [0, 1])]  # partial curves of a network could overlap
    ifem.write_curves(tmp_path / "c.txt", curves)
    for fn in (ifem.curve_poisson, ifem.curve_distance):
        with pytest.raises(ifem.InvalidInput, match=r"iteration cap \(3 reroutes.*accept"):
            fn(V, F, curves, max_iterations=3)
    for fn, cmd in ((ifem.curve_poisson, "poisson"), (ifem.curve_distance, "distance")):
        run_cli(cmd, SPOT, "--curves", tmp_path / "c.txt", "--max-iterations", 3,
                "--accept-partial", "-o", tmp_path / "x.txt", "--quiet")
        x, info = fn(V, F, curves, max_iterations=3, accept_partial=True, return_info=True)
        assert info["flipout"]["stopped_by"] == "iteration cap"
        assert info["flipout"]["iterations"] == 3
        assert abs(x - read_txt(tmp_path / "x.txt")).max() <= 1e-12
        full, info = fn(V, F, curves, return_info=True)
        assert info["flipout"]["stopped_by"] != "iteration cap"
        assert abs(full - x).max() > 1e-6  # the cap matters
    for bad in (-1, 2.5, "3", True):
        with pytest.raises(ifem.InvalidInput, match="max_iterations must be an integer ≥ 0"):
            ifem.curve_distance(V, F, curves, max_iterations=bad)


def test_flat_grid_file_matches_cli(tmp_path):
    n = 12
    V, F = flat_grid(n)
    write_obj(tmp_path / "sq.obj", V, F)
    curves = [ifem.Curve(row(n, 3), 0), ifem.Curve([5, 100, 140], [1, 2, 3])]
    ifem.write_curves(tmp_path / "c.txt", curves)
    run_cli("poisson", tmp_path / "sq.obj", "--curves", tmp_path / "c.txt", "-o",
            tmp_path / "u.txt", "--quiet")
    u = ifem.curve_poisson(V, F, curves)
    assert abs(u - read_txt(tmp_path / "u.txt")).max() <= 1e-12


# ---- known truth on a flat square ----------------------------------------------------------

@pytest.mark.parametrize("refine", [False, True])
def test_two_straight_curves_give_the_exact_ramp(refine):
    # u = 0 on y = a, 1 on y = b, natural conditions elsewhere: the solution is 0 below a,
    # linear between, 1 above b. The curves cross the jittered triangles as single intrinsic
    # edges, so P1 elements reproduce it exactly at every vertex (not only near the curves).
    n, ra, rb = 16, 5, 11
    V, F = flat_grid(n)
    a, b = ra / n, rb / n
    u, info = ifem.curve_poisson(V, F, [ifem.Curve(row(n, ra), 0), ifem.Curve(row(n, rb), 1)],
                                 refine=refine, min_angle=28, resolution=0.5, return_info=True)
    ramp = np.clip((V[:, 1] - a) / (b - a), 0, 1)
    assert abs(u - ramp).max() <= 1e-9
    assert info["conflicting_vertices"] == 0 and info["slit_copies"] == 0
    assert (info["vertices"] > len(V)) == refine
    assert info["curve_lengths"] == pytest.approx([1.0, 1.0], abs=1e-12)


def test_values_linear_in_arc_length():
    n, r = 16, 6
    V, F = flat_grid(n, straight_rows=(r,))
    on = np.arange(r * (n + 1), (r + 1) * (n + 1))  # the row's vertices, all on the curve
    for refine in (False, True):
        u = ifem.curve_poisson(V, F, [ifem.Curve(row(n, r), [2.0, 5.0])], refine=refine)
        assert abs(u[on] - (2 + 3 * V[on, 0])).max() <= 1e-12


def test_slit_separates_the_sides():
    # a slit across the square at y = a, 1 on its left (walking +x, seen from +z: above), 0 on
    # its right: u is 1 above and 0 below; its two end vertices lie on it and take the mean
    n, r = 16, 5
    V, F = flat_grid(n)
    u = ifem.curve_poisson(V, F, [ifem.Curve(row(n, r), left=1, right=0)])
    ends = row(n, r)
    off = np.setdiff1d(np.arange(len(V)), ends)
    assert abs(u[off] - (V[off, 1] > r / n)).max() <= 1e-9
    assert np.allclose(u[ends], 0.5, atol=1e-12)
    # reversed, the sides swap
    u2 = ifem.curve_poisson(V, F, [ifem.Curve(row(n, r)[::-1], left=1, right=0)])
    assert abs(u2[off] - (V[off, 1] < r / n)).max() <= 1e-9


def test_distance_to_a_straight_curve():
    n, r = 16, 5
    V, F = flat_grid(n, straight_rows=(r,))
    on = np.arange(r * (n + 1), (r + 1) * (n + 1))
    exact = np.abs(V[:, 1] - r / n)
    d = ifem.curve_distance(V, F, [ifem.Curve(row(n, r))])
    assert (d[on] == 0).all()
    assert abs(d - exact).max() < 0.04 and abs(d - exact).mean() < 0.01
    dr = ifem.curve_distance(V, F, [ifem.Curve(row(n, r))], refine=True)
    assert (dr[on] == 0).all()
    assert abs(dr - exact).max() < 0.02 and abs(dr - exact).mean() < abs(d - exact).mean() / 2


def test_crossing_curves_meet_at_a_vertex_with_the_mean():
    n = 12
    V, F = flat_grid(n)
    c1 = ifem.Curve([2 * (n + 1), 10 * (n + 1) + n], 0)
    c2 = ifem.Curve([10 * (n + 1), 2 * (n + 1) + n], 1)
    u, lines, info = ifem.curve_poisson(V, F, [c1, c2], return_polylines=True, return_info=True)
    assert info["conflicting_vertices"] >= 1
    assert u.min() >= -1e-12 and u.max() <= 1 + 1e-12
    shared = [p for p in lines[0] if (np.abs(lines[1] - p).sum(axis=1) <= 1e-12).any()]
    assert len(shared) >= 1


# ---- the Curve class and the file format ---------------------------------------------------

def test_curve_lines_and_round_trip(tmp_path):
    table = [
        (ifem.Curve([12, 40, 77], 0.5), "0.5 12 40 77"),
        (ifem.Curve([5, 9, 13], 1, closed=True), "closed 1.0 5 9 13"),
        (ifem.Curve([3, 8, 20, 31], 0, bezier=True), "bezier=4 0.0 3 8 20 31"),
        (ifem.Curve([3, 8, 20, 31], [0, 1], bezier=6), "bezier=6 0.0 1.0 : 3 8 20 31"),
        (ifem.Curve([12, 40, 77], [0, 0.5, 1]), "0.0 0.5 1.0 : 12 40 77"),
        (ifem.Curve([12, 40, 77], left=0, right=1), "slit 0.0 1.0 12 40 77"),
        (ifem.Curve([12, 77], left=[0, 1], right=[1, 0]), "slit 0.0 1.0 : 1.0 0.0 : 12 77"),
        (ifem.Curve(np.array([1, 2], np.uint8), 0.1 + 0.2), "0.30000000000000004 1 2"),
    ]
    for curve, line in table:
        assert curve.to_line() == line
    ifem.write_curves(tmp_path / "c.txt", [c for c, _ in table])
    back = ifem.read_curves(tmp_path / "c.txt")
    assert back == [c for c, _ in table]
    assert back[0].origin == f"{tmp_path / 'c.txt'}:1" and back[1].shape == "loop"
    assert back[5].slit and back[5].value is None and back[5].left.tolist() == [0.0]
    assert back[3].bezier == 6 and back[2].bezier == 4 and back[0].bezier is None
    assert back[7].value[0] == 0.1 + 0.2  # numbers round-trip exactly


def test_curves_as_dicts_and_a_single_curve():
    n = 8
    V, F = flat_grid(n)
    u1 = ifem.curve_poisson(V, F, [{"vertices": row(n, 2), "value": 0},
                                   {"vertices": row(n, 6), "value": 1}])
    u2 = ifem.curve_poisson(V, F, [ifem.Curve(row(n, 2), 0), ifem.Curve(row(n, 6), 1)])
    assert np.array_equal(u1, u2)
    d1 = ifem.curve_distance(V, F, ifem.Curve(row(n, 2)))
    d2 = ifem.curve_distance(V, F, {"vertices": row(n, 2), "value": 3})  # values are ignored
    assert np.array_equal(d1, d2)


# ---- bad input ---------------------------------------------------------------------------

def test_bad_curves_raise_with_a_clear_message():
    C = ifem.Curve
    bad = [
        (lambda: C([3]), "Curve: a curve needs at least 2 vertices, got 1"),
        (lambda: C([3, 3], 1), r"Curve: vertex 3 twice in a row \(positions 1 and 2\)"),
        (lambda: C([0, 1], np.nan), "Curve: value 1 is not a finite number"),
        (lambda: C([0, 1], left=[0, np.inf], right=[1, 1]), "Curve: value 2 is not a finite"),
        (lambda: C([0, 1, 2], [0, 1]), "2 values for a path of 3 vertices: expected 1"),
        (lambda: C([0, 1, 2], [0, 1, 2], bezier=2), r"3 values for a Bézier curve .* \(at its "
                                                    "ends\\)"),
        (lambda: C([0, 1], left=[0, 1], right=[1]), "2 left values and 1 right values"),
        (lambda: C([0, 1], left=0), "a slit needs both left and right values"),
        (lambda: C([0, 1], 0, left=0, right=1), "value .* or left and right .*, not both"),
        (lambda: C([0, 1], 1, bezier=17), r"bezier must be True or a number of rounds in "
                                          r"\[0, 16\], got 17"),
        (lambda: C([0, 1], 1, bezier=2.5), "bezier must be True or a number of rounds"),
        (lambda: C([0, 1, 2], 1, bezier=3, closed=True), "closed or Bézier, not both"),
        (lambda: C([4, 1, 4], 1, closed=True), "a closed curve's last vertex 4 is its first"),
        (lambda: C([0, -1], 1), r"vertices\[1\] = -1 is negative"),
        (lambda: C([0, 1.5], 1), "vertices must be a 1-D list of vertex ids"),
        (lambda: C([0, 1], "high"), "value must be a number or a list of numbers"),
        (lambda: C([0, 1], [[0, 1]]), "value must be a number or a 1-D list"),
    ]
    for call, message in bad:
        with pytest.raises(ifem.InvalidInput, match=message):
            call()


def test_bad_solver_input_raises_with_a_clear_message(tmp_path):
    n = 8
    V, F = flat_grid(n)
    nv = len(V)
    C = ifem.Curve
    ok = [C(row(n, 2), 0)]
    bad = [
        (lambda: ifem.curve_poisson(V, F, [C([0, nv], 1)]), ifem.InvalidInput,
         rf"curves\[0\]: vertex {nv} out of range \[0, {nv}\)"),
        (lambda: ifem.curve_poisson(V, F, ok + [{"vertices": [5, 6], "value": np.nan}]),
         ifem.InvalidInput, r"curves\[1\]: value 1 is not a finite number"),
        (lambda: ifem.curve_poisson(V, F, ok + [{"vertices": [5], "value": 1}]),
         ifem.InvalidInput, r"curves\[1\]: a curve needs at least 2 vertices"),
        (lambda: ifem.curve_poisson(V, F, ok + [{"vertices": [5, 6], "valu": 1}]),
         ifem.InvalidInput, r"curves\[1\]: .*unexpected keyword argument 'valu'"),
        (lambda: ifem.curve_poisson(V, F, ok + [C([5, 6])]), ifem.InvalidInput,
         r"curves\[1\]: the curve carries no value"),
        (lambda: ifem.curve_poisson(V, F, [C(row(n, 2), 0), C(row(n, 2), 1)]),
         ifem.InvalidInput, r"curves\[1\] and curve at curves\[0\] share the edge"),
        (lambda: ifem.curve_poisson(V, F, [C(row(n, 2) + [n * (n + 1)], 0, closed=False),
                                           C([n * (n + 1), row(n, 2)[1]], 1)]),
         ifem.InvalidInput, "share the edge"),
        (lambda: ifem.curve_poisson(V, F, []), ifem.InvalidInput, "curves is empty"),
        (lambda: ifem.curve_poisson(V, F, "not a list.txt"), ifem.IoError, "cannot open"),
        (lambda: ifem.curve_poisson(V, F, 42), ifem.InvalidInput, "curves must be a list"),
        (lambda: ifem.curve_poisson(V, F, [42]), ifem.InvalidInput,
         r"curves\[0\] must be an ifem.Curve"),
        (lambda: ifem.curve_poisson(V, F, ok, rhs=np.ones(3)), ifem.InvalidInput,
         f"rhs must have {nv} values, got 3"),
        (lambda: ifem.curve_poisson(V, F, ok, rhs=np.full(nv, np.nan)), ifem.InvalidInput,
         r"rhs\[0\] is not finite"),
        (lambda: ifem.curve_poisson(V, F, ok, dirichlet={nv: 1}), ifem.InvalidInput,
         rf"dirichlet vertices\[0\] = {nv} is out of range"),
        (lambda: ifem.curve_poisson(V, F, ok, dirichlet={5: np.nan}), ifem.InvalidInput,
         r"dirichlet values\[0\] is not finite"),
        (lambda: ifem.curve_poisson(V, F, ok, dirichlet={row(n, 2)[0]: 1}), ifem.InvalidInput,
         "lies on a curve"),
        (lambda: ifem.curve_poisson(V, F, ok, dirichlet=[1, 2, 3]), ifem.InvalidInput,
         "dirichlet must be a dict"),
        (lambda: ifem.curve_poisson(V, F, ok, screening=-1), ifem.InvalidInput,
         "screening must be finite and ≥ 0"),
        (lambda: ifem.curve_poisson(V, F, ok, refine=True, min_angle=35), ifem.InvalidInput,
         r"min_angle must be in \(0, 30\]"),
        (lambda: ifem.curve_poisson(V, F, ok, refine=True, resolution=-1), ifem.InvalidInput,
         "resolution must be finite"),
        (lambda: ifem.curve_poisson(V, F, ok, mollify=2), ifem.InvalidInput, "mollify must be"),
        (lambda: ifem.curve_distance(V, F, ok, time_factor=0), ifem.InvalidInput,
         "time_factor must be finite and > 0"),
        (lambda: ifem.curve_distance(V, F, ok, correction_steps=-1), ifem.InvalidInput,
         "correction_steps must be ≥ 0"),
        (lambda: ifem.curve_distance(V, np.zeros((0, 3), int), ok), ifem.InvalidInput,
         "curves need a triangle mesh"),
    ]
    for call, exc, message in bad:
        with pytest.raises(exc, match=message):
            call()


def test_bad_curves_file(tmp_path):
    V, F = flat_grid(4)
    p = tmp_path / "c.txt"
    p.write_text("0.5 1 2\nslit 0 1 : 2\n")
    with pytest.raises(ifem.IoError, match=r"c.txt:2: "):
        ifem.read_curves(p)
    p.write_text("# nothing\n\n")
    with pytest.raises(ifem.IoError, match="no curve in the file"):
        ifem.curve_distance(V, F, p)
    p.write_text("0.5 1 2\n0.5 3 99\n")
    with pytest.raises(ifem.InvalidInput, match=r"c.txt:2: vertex 99 out of range \[0, 25\)"):
        ifem.curve_poisson(V, F, p)


def test_nonmanifold_mesh_is_refused():
    n = 4
    V, F = flat_grid(n)
    V = np.r_[V, [[0.1, 0.1, 1.0]]]
    F = np.r_[F, [[6, 7, len(V) - 1]]]  # a third triangle on the interior edge 6–7
    with pytest.raises(ifem.InvalidInput, match="curves need an edge-manifold, orientable mesh"):
        ifem.curve_poisson(V, F, [ifem.Curve(row(n, 2), 0)])


def holey_scan(seed):
    """tests/data/make_holey_scan.py's mesh with many small holes and its hard curves."""
    import sys
    sys.path.insert(0, str(conftest.TEST_DATA))
    import make_holey_scan as m
    V, F = m.holey_scan(seed=seed)
    curves = [ifem.Curve(vertices, values if len(values) > 1 else values[0])
              for vertices, values in m.hard_curves(V)]
    return np.array(V, float), np.array(F, np.int64), curves


# Refined curve problems keep the maximum principle (conforming refinement: curve and boundary
# edges with negative cotan weights are split); conform=False keeps those weights.
@pytest.mark.parametrize("seed", [4, 7])
def test_curve_poisson_refined_keeps_the_maximum_principle(seed):
    V, F, curves = holey_scan(seed)
    u, info = ifem.curve_poisson(V, F, curves, refine=True, return_info=True)
    assert info["conforming_splits"] > 0
    assert info["negative_barrier_weights"] == 0
    assert info["negative_weights_on_curves"] == 0 and info["negative_weights_elsewhere"] == 0
    assert u.min() >= -1e-12 and u.max() <= 1 + 1e-12
    u0, info0 = ifem.curve_poisson(V, F, curves, refine=True, conform=False, return_info=True)
    assert info0["conforming_splits"] == 0
    assert info0["negative_weights_on_curves"] + info0["negative_weights_elsewhere"] > 0
