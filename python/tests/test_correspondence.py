"""correspondence= (signposts | integer) on refine, distance, HeatDistanceSolver, eigen and
poisson: both give the same results on spot; a refined triangulation of either kind saves and
loads back the same common subdivision and positions; bad choices are refused by name."""

import numpy as np
import pytest

import ifem
from conftest import test_data

KINDS = ("signposts", "integer")


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(test_data("spot.obj"))


def test_refine_both_kinds_agree_and_round_trip(spot, tmp_path):
    r = {k: ifem.refine(*spot, min_angle=28, correspondence=k) for k in KINDS}
    assert r["signposts"].correspondence == "signposts"
    assert r["integer"].correspondence == "integer"
    a, b = r["signposts"], r["integer"]
    assert a.n_vertices == b.n_vertices > spot[0].shape[0]
    assert np.array_equal(a.faces(), b.faces())
    assert np.array_equal(a.edge_lengths(), b.edge_lengths())
    assert np.max(np.abs(a.positions() - b.positions())) <= 1e-9
    x = np.sin(3 * spot[0][:, 0]) + spot[0][:, 2]
    assert np.max(np.abs(a.from_input(x) - b.from_input(x))) <= 1e-9
    _, _, fa, ia = a.common_subdivision()
    _, _, fb, ib = b.common_subdivision()
    assert set(zip(fa, ia)) == set(zip(fb, ib))  # the same polygons
    for k in KINDS:
        path = tmp_path / f"{k}.ifem"
        r[k].save(path)
        back = ifem.load_refined(path)
        assert back.correspondence == k
        assert back.report is None
        assert np.array_equal(back.positions(), r[k].positions())
        for mine, theirs in zip(back.common_subdivision(), r[k].common_subdivision()):
            assert np.array_equal(mine, theirs)


def test_default_is_integer(spot):
    """Integer coordinates by default (D-330), everywhere a refinement takes the keyword."""
    V, F = spot
    assert ifem.refine(V, F, min_angle=20).correspondence == "integer"
    s = ifem.HeatDistanceSolver(V, F, refine=True, resolution=0)
    assert s.info["correspondence"] == "integer" and not s.info["signposts"]
    _, info = ifem.poisson(V, F, dirichlet={0: 0.0, 100: 1.0}, refine=True, return_info=True)
    assert info["correspondence"] == "integer"
    _, _, info = ifem.eigen(V, F, 2, refine=True, return_info=True)
    assert info["correspondence"] == "integer"
    assert ifem.HeatDistanceSolver(V, F).info["correspondence"] is None  # not refined


def test_solvers_keyword(spot):
    V, F = spot
    d = {k: ifem.distance(V, F, [0], refine=True, resolution=0, correspondence=k) for k in KINDS}
    assert np.max(np.abs(d["signposts"] - d["integer"])) <= 1e-9
    s = ifem.HeatDistanceSolver(V, F, refine=True, resolution=0, correspondence="integer")
    assert np.max(np.abs(s.compute_distance([0]) - d["integer"])) <= 1e-12
    ev = {k: ifem.eigen(V, F, 3, refine=True, correspondence=k)[0] for k in KINDS}
    assert np.max(np.abs(ev["signposts"] - ev["integer"])) <= 1e-9 * np.max(ev["signposts"])
    f = np.cos(2 * V[:, 1])
    u = {k: ifem.poisson(V, F, f, {0: 0.0, 100: 1.0}, refine=True, correspondence=k)
         for k in KINDS}
    assert np.max(np.abs(u["signposts"] - u["integer"])) <= 1e-9


def test_relax_with_integer_coordinates(spot):
    """relax with integer coordinates: the same moves and mesh as with signposts."""
    V, F = spot
    r = {k: ifem.refine(V, F, relax=2, correspondence=k) for k in KINDS}
    s, i = r["signposts"], r["integer"]
    assert s.report["relax"]["moved"] > 0
    assert s.report["relax"]["moved"] == i.report["relax"]["moved"]
    assert np.array_equal(s.faces(), i.faces())
    assert np.max(np.abs(s.positions() - i.positions())) <= 1e-9 * np.ptp(V, axis=0).max()


def test_bad_choices(spot):
    V, F = spot
    with pytest.raises(ifem.InvalidInput, match="'ints' is neither 'signposts' nor 'integer'"):
        ifem.refine(V, F, correspondence="ints")
    with pytest.raises(ifem.InvalidInput, match="correspondence only apply with refine=True"):
        ifem.distance(V, F, [0], correspondence="signposts")
    with pytest.raises(ifem.InvalidInput, match="neither"):
        ifem.distance(V, F, [0], refine=True, correspondence="exact")
    with pytest.raises(ifem.InvalidInput, match="must be 'signposts' or 'integer'"):
        ifem.eigen(V, F, 3, refine=True, correspondence=1)
    with pytest.raises(ifem.InvalidInput, match="neither"):
        ifem.poisson(V, F, curves=[ifem.Curve([0, 100], 1.0)], refine=True,
                     correspondence="ints")


def test_curves_both_kinds_agree(spot):
    """Curves with integer coordinates (FlipOut's operations replayed on them): the same
    Poisson values, distances and traced curves as with signposts."""
    V, F = spot
    curves = [ifem.Curve([0, 764], 0.0), ifem.Curve([813, 1200, 2000], 1.0)]
    u, lines, info = {}, {}, {}
    for k in KINDS:
        u[k], lines[k], info[k] = ifem.curve_poisson(V, F, curves, refine=True, resolution=0.8,
                                                     correspondence=k, return_polylines=True,
                                                     return_info=True)
    assert np.ptp(u["signposts"]) > 0.5
    assert np.max(np.abs(u["signposts"] - u["integer"])) <= 1e-9
    for a, b in zip(lines["signposts"], lines["integer"]):
        assert a.shape == b.shape and np.max(np.abs(a - b)) <= 1e-6
    d = {k: ifem.distance(V, F, curves=curves, refine=True, resolution=0.8, correspondence=k)
         for k in KINDS}
    assert np.max(np.abs(d["signposts"] - d["integer"])) <= 1e-9
    p = {k: ifem.poisson(V, F, curves=curves, refine=True, resolution=0.8, correspondence=k)
         for k in KINDS}
    assert np.max(np.abs(p["signposts"] - p["integer"])) <= 1e-9
    # signed distance to the curves, refined with either kind (the keyword reaches it too)
    loop = [ifem.Curve([100, 900, 1700], 0.0, closed=True)]
    sd = {k: ifem.signed_distance(V, F, loop, refine=True, resolution=0.8, correspondence=k)
          for k in KINDS}
    assert np.ptp(sd["integer"]) > 0
    assert np.max(np.abs(sd["signposts"] - sd["integer"])) <= 1e-9


def _flat_grid(n=6):
    xs, ys = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    rng = np.random.default_rng(3)
    V = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    inner = (V[:, 0] > 0) & (V[:, 0] < 1) & (V[:, 1] > 0) & (V[:, 1] < 1)
    V[inner, :2] += rng.uniform(-0.3, 0.3, (inner.sum(), 2)) / n
    F = []
    for j in range(n):
        for i in range(n):
            a, b = j * (n + 1) + i, j * (n + 1) + i + 1
            F += [[a, b, b + n + 1], [a, b + n + 1, a + n + 1]]
    return V, np.array(F)


def _lumped_mass(V, F):
    area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    m = np.zeros(len(V))
    for k in range(3):
        np.add.at(m, F[:, k], area / 3)
    return m


@pytest.mark.parametrize("kind", KINDS)
def test_transfer_linear_exact_on_flat_and_l2_keeps_the_integral(spot, kind):
    V, F = _flat_grid()
    r = ifem.refine(V, F, min_angle=28, max_area=0.004, correspondence=kind)
    assert r.n_vertices > len(V)
    lin = lambda P: 0.4 + 1.3 * P[:, 0] - 0.7 * P[:, 1]  # noqa: E731
    for method in ("pointwise", "l2"):
        u = ifem.transfer(r, lin(V), method=method)
        assert np.max(np.abs(u - lin(r.positions()))) <= 1e-10
        back = ifem.transfer(r, lin(r.positions()), method, back=True)
        assert np.max(np.abs(back - lin(V))) <= 1e-10
    f = np.sin(3 * spot[0][:, 0]) + spot[0][:, 2]
    s = ifem.refine(*spot, min_angle=25, correspondence=kind)
    u = ifem.transfer(s, f, "l2")
    _, M = s.laplacian()
    assert u[:len(f)].shape == f.shape
    expected = _lumped_mass(*spot) @ f
    assert abs(M.diagonal() @ u - expected) <= 1e-12 * abs(expected)
    assert np.array_equal(ifem.transfer(s, f, "pointwise")[:len(f)], f)


def test_transfer_refuses_bad_input_with_the_reason(spot):
    r = ifem.refine(*spot, min_angle=25)
    f = np.zeros(len(spot[0]))
    with pytest.raises(ifem.InvalidInput, match="pointwise"):
        ifem.transfer(r, f, method="cubic")
    with pytest.raises(ifem.InvalidInput):
        ifem.transfer(r, f, back=True)  # needs one value per refined vertex
    with pytest.raises(ifem.InvalidInput, match="RefinedTriangulation"):
        ifem.transfer(spot, f)
