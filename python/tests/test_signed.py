"""signed_distance: against the Euclidean distance to a circle on a jittered flat square (closed,
and with 20 % of its arc missing; negative inside, positive outside), oriented points on the
same square as a mesh and as a point cloud, the CLI's output (`ifem distance --signed`, same
mesh and curves file, 1e-12), and bad input."""

import numpy as np
import pytest

import conftest
import ifem
from conftest import read_txt, run_cli

N = 30  # the unit square, h ≈ 1/30
C, R = np.array([0.5, 0.5]), 0.25


@pytest.fixture(scope="module")
def grid():
    return conftest.flat_grid(N)


def circle(V, k, arc=1.0):
    """Vertices nearest to k points of the circle, counter-clockwise over `arc` of the turn."""
    a = 2 * np.pi * arc * np.arange(k) / (k if arc >= 1 else k - 1)
    pts = C + R * np.stack([np.cos(a), np.sin(a)], 1)
    ids = [int(np.argmin(((V[:, :2] - p) ** 2).sum(1))) for p in pts]
    return [v for i, v in enumerate(ids) if i == 0 or v != ids[i - 1]]


def check(d, V, keep=None):
    exact = np.linalg.norm(V[:, :2] - C, axis=1) - R
    keep = np.ones(len(V), bool) if keep is None else keep
    far = keep & (np.abs(exact) > 0.05)
    assert np.all(d[far] * exact[far] > 0), "wrong sign"
    near = keep & (np.abs(exact) < 0.2)
    err = np.abs(np.abs(d[near]) - np.abs(exact[near])).mean()
    assert err < 0.01, err  # ~0.3 h; the curve is a polygon through grid vertices
    return err


def test_closed_and_broken_circle(grid, tmp_path):
    V, F = grid
    loop = circle(V, 32)
    d, info = ifem.signed_distance(V, F, [ifem.Curve(loop, closed=True)], return_info=True)
    assert info["unreached_vertices"] == 0 and info["time_step"] > 0
    assert np.all(d[loop] == 0)
    check(d, V)
    # the CLI on the same mesh and curves file
    mesh, curves, out = tmp_path / "sq.obj", tmp_path / "c.txt", tmp_path / "d.txt"
    with open(mesh, "w") as f:
        f.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)
    ifem.write_curves(curves, [ifem.Curve(loop, 0.0, closed=True)])
    run_cli("distance", mesh, "--signed", "--curves", curves, "-o", out, "--quiet")
    assert np.abs(read_txt(out) - d).max() < 1e-12
    # 20 % of the arc missing: right away from the gap, the centre still inside
    arc = circle(V, 27, 0.8)
    db = ifem.signed_distance(V, F, [ifem.Curve(arc)], level_set="mean")
    ang = np.arctan2(V[:, 1] - C[1], V[:, 0] - C[0]) % (2 * np.pi)
    check(db, V, (ang > 0.1 * 2 * np.pi) & (ang < 0.7 * 2 * np.pi))
    assert db[np.argmin(((V[:, :2] - C) ** 2).sum(1))] < -0.15


def test_oriented_points_mesh_and_cloud(grid):
    V, F = grid
    ids = circle(V, 40)
    normals = np.zeros((len(ids), 3))
    normals[:, :2] = V[ids, :2] - C
    check(ifem.signed_distance(V, F, points=ids, point_normals=normals), V)
    up = np.tile([0.0, 0.0, 1.0], (len(V), 1))
    d, info = ifem.signed_distance(V, None, points=ids, point_normals=normals, normals=up,
                                   return_info=True)
    assert info["path"] == "pointcloud"
    check(d, V)


def test_bad_input(grid):
    V, F = grid
    with pytest.raises(ifem.InvalidInput, match="curves or points"):
        ifem.signed_distance(V, F)
    with pytest.raises(ifem.InvalidInput, match="normal to the surface"):
        ifem.signed_distance(V, F, points=[5], point_normals=[[0, 0, 1]])
    with pytest.raises(ifem.InvalidInput, match="one row per point"):
        ifem.signed_distance(V, F, points=[5, 6], point_normals=[[1, 0, 0]])
    with pytest.raises(ifem.InvalidInput, match="expected 'zero-set' or 'mean'"):
        ifem.signed_distance(V, F, points=[5], point_normals=[[1, 0, 0]], level_set="zero")
    with pytest.raises(ifem.InvalidInput, match="time_factor"):
        ifem.signed_distance(V, F, points=[5], point_normals=[[1, 0, 0]], time_factor=0)
