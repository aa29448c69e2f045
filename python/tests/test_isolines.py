"""ifem.isolines: every point on its level (edge crossing, surface point, position), the pieces
the topology gives (a sphere's loops, a flat grid's open curves), a file's property by name, the
same curves as `ifem isolines`; argument checking. Also ifem.distance(path_bounds=False)."""

import numpy as np
import pytest

import ifem
from conftest import flat_grid, run_cli, test_data


def check_on_level(V, F, f, iso):
    for k in range(len(iso)):
        a, b = iso.offsets[k], iso.offsets[k + 1]
        assert b - a >= 2
        c = iso.value[k]
        lo, hi, t = iso.below[a:b], iso.above[a:b], iso.t[a:b]
        vertex = lo == hi
        assert np.all(f[hi[vertex]] == c)
        assert np.all(f[lo[~vertex]] < c) and np.all(f[hi[~vertex]] > c)
        assert np.allclose((1 - t) * f[lo] + t * f[hi], c, rtol=0, atol=1e-12)
        x = (1 - t)[:, None] * V[lo] + t[:, None] * V[hi]
        assert np.allclose(x, iso.points[a:b], rtol=0, atol=1e-14)
        bary = iso.bary[a:b]
        y = np.einsum("ij,ijk->ik", bary, V[F[iso.faces[a:b]]])
        assert np.allclose(y, iso.points[a:b], rtol=0, atol=1e-14)
        assert np.all(bary >= 0) and np.allclose(bary.sum(1), 1)


def test_sphere_distance_one_loop_per_level():
    # a unit uv sphere: poles 0 and 1, 23 rings of 39 vertices
    th, ph = np.meshgrid(np.linspace(0, np.pi, 25)[1:-1], np.linspace(0, 2 * np.pi, 40)[:-1],
                         indexing="ij")
    V = np.vstack([[0, 0, 1], [0, 0, -1],
                   np.c_[(np.sin(th) * np.cos(ph)).ravel(), (np.sin(th) * np.sin(ph)).ravel(),
                         np.cos(th).ravel()]])
    n_lat, n_lon = th.shape
    ring = lambda i, j: 2 + i * n_lon + j % n_lon  # noqa: E731
    F = []
    for j in range(n_lon):
        F += [(0, ring(0, j), ring(0, j + 1)), (1, ring(n_lat - 1, j + 1), ring(n_lat - 1, j))]
        for i in range(n_lat - 1):
            F += [(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)),
                  (ring(i, j), ring(i + 1, j + 1), ring(i, j + 1))]
    F = np.array(F)
    d = ifem.distance(V, F, 0)
    iso = ifem.isolines(V, F, d, count=5)
    assert len(iso) == 5 and iso.closed.all()
    assert list(iso.level) == [0, 1, 2, 3, 4]
    assert iso.levels == pytest.approx(np.linspace(0, d.max(), 7)[1:-1], rel=1e-15)
    check_on_level(V, F, d, iso)
    # several levels of the exact field z at once, values unsorted, plus one at vertices
    z = V[:, 2]
    iso = ifem.isolines(V, F, z, values=[0.5, -0.3, z[2]])
    assert len(iso) == 3 and iso.closed.all() and list(iso.value) == [0.5, -0.3, z[2]]
    check_on_level(V, F, z, iso)
    a, b = iso.offsets[2], iso.offsets[3]
    assert np.all(iso.below[a:b] == iso.above[a:b])  # the ring of vertices at z[2], each once
    assert b - a == n_lon
    loops = iso.polylines()
    assert all(np.array_equal(p[0], p[-1]) for p in loops)


def test_flat_grid_open_curves_and_cli(tmp_path):
    V, F = flat_grid(12)
    f = V[:, 0] + 0.3 * V[:, 1]
    iso = ifem.isolines(V, F, f, values=np.array([0.2, 0.7, 1.1]))
    assert len(iso) == 3 and not iso.closed.any()
    check_on_level(V, F, f, iso)
    for p in iso.polylines():
        for end in (p[0], p[-1]):
            assert min(end[0], 1 - end[0], end[1], 1 - end[1]) < 1e-12
    # a file's property by name, and the CLI's curves from the same field
    ifem.write_ply(tmp_path / "g.ply", V, F, binary=False, h=f)
    iso2 = ifem.isolines(tmp_path / "g.ply", f="h", values=0.7)
    assert np.array_equal(iso2.points, iso.points[iso.offsets[1]:iso.offsets[2]])
    run_cli("isolines", tmp_path / "g.ply", tmp_path / "g.ply", "--values", "0.2,0.7,1.1", "-o",
            tmp_path / "iso.obj", "--quiet")
    pts = np.array([[float(x) for x in line.split()[1:]]
                    for line in open(tmp_path / "iso.obj") if line.startswith("v ")])
    assert np.array_equal(pts, iso.points)


def test_isolines_bad_arguments():
    V, F = flat_grid(4)
    f = V[:, 0]
    with pytest.raises(ifem.InvalidInput, match=r"outside the field's range \[0, 1\]"):
        ifem.isolines(V, F, f, values=[0.5, 2.0])
    with pytest.raises(ifem.InvalidInput, match="exactly one of values"):
        ifem.isolines(V, F, f)
    with pytest.raises(ifem.InvalidInput, match="exactly one of values"):
        ifem.isolines(V, F, f, values=[0.5], count=2)
    with pytest.raises(ifem.InvalidInput, match="f has 3 values, V 25 rows"):
        ifem.isolines(V, F, f[:3], count=2)
    with pytest.raises(ifem.InvalidInput, match="count must be an integer"):
        ifem.isolines(V, F, f, count=2.5)
    with pytest.raises(ifem.InvalidInput, match="count of levels must be"):
        ifem.isolines(V, F, f, count=0)
    with pytest.raises(ifem.InvalidInput, match="need a mesh with faces"):
        ifem.isolines(V, None, f, count=1)
    with pytest.raises(ifem.InvalidInput, match="no per-vertex property 'u'"):
        ifem.isolines(test_data("fan3.obj"), f="u", count=1)


def test_distance_path_bounds_switch():
    V, F = flat_grid(16, jitter=0.35)
    exact = np.linalg.norm(V - V[0], axis=1)
    on = ifem.distance(V, F, 0)
    off = ifem.distance(V, F, 0, path_bounds=False)
    assert np.all(np.abs(on - exact) <= np.abs(off - exact) + 1e-12)
    assert np.sum(~np.isclose(on, off, rtol=1e-9, atol=0)) > 10
    assert off.min() == 0 and np.any(off < exact - 1e-4)
    solver = ifem.HeatDistanceSolver(V, F, path_bounds=False)
    assert solver.info["path_bounds"] is False
    assert np.array_equal(solver.compute_distance(0), off)
    assert ifem.HeatDistanceSolver(V, F).info["path_bounds"] is True
    with pytest.raises(ifem.InvalidInput, match="path_bounds must be True or False"):
        ifem.distance(V, F, 0, path_bounds="no")


def test_curve_distance_path_bounds_switch():
    V, F = flat_grid(12, jitter=0.35)
    loop = ifem.Curve([14, 20, 98, 92], closed=True)
    on = ifem.distance(V, F, curves=[loop])
    off = ifem.distance(V, F, curves=[loop], path_bounds=False)
    assert np.all(on <= off + 1e-12)  # the clamp here is the upper bound only
    assert np.any(on < off - 1e-9)
