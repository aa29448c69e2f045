"""laplacian / point_cloud_laplacian: against the CLI's matrices (same meshes, 1e-12), the
sparse-matrix invariants, and an analytic answer (the flat Poisson problem)."""

import numpy as np
import pytest
import scipy.sparse
import scipy.sparse.linalg

import ifem
from conftest import flat_grid, read_matrix_market, run_cli, shared_data, test_data


def assert_laplacian_invariants(L, M, n):
    assert isinstance(L, scipy.sparse.csc_matrix) and isinstance(M, scipy.sparse.csc_matrix)
    assert L.shape == (n, n) and M.shape == (n, n)
    scale = abs(L.diagonal()).max()
    assert abs(L - L.T).max() <= 1e-14 * scale                      # symmetric
    assert abs(L @ np.ones(n)).max() <= 1e-12 * scale                # constants in the kernel
    off = L - scipy.sparse.diags(L.diagonal())
    assert off.max() <= 1e-10 * scale                                # IDT: weights ≥ 0
    assert (M.diagonal() >= 0).all() and M.count_nonzero() == (M.diagonal() > 0).sum()


def nonmanifold_obj(tmp_path):
    """A fan of three flaps on one edge plus a square: an edge with three faces."""
    p = tmp_path / "flaps.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0.2\nv 0.5 0.1 1\nv 1.5 1 0\n"
                 "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 2 6 3\n")
    return p


@pytest.mark.parametrize("mesh", ["spot", "nonmanifold"])
def test_laplacian_matches_cli(tmp_path, mesh):
    path = test_data("spot.obj") if mesh == "spot" else nonmanifold_obj(tmp_path)
    V, F = ifem.read_mesh(path)
    L, M, info = ifem.laplacian(V, F, return_info=True)
    run_cli("laplacian", path, "-o", tmp_path / "x", "--quiet")
    Lc, Mc = read_matrix_market(tmp_path / "x_L.mtx"), read_matrix_market(tmp_path / "x_M.mtx")
    scale = abs(Lc).max()
    assert abs(L - Lc).max() <= 1e-12 * scale
    assert abs(M - Mc).max() <= 1e-12 * abs(Mc).max()
    assert_laplacian_invariants(L, M, len(V))
    assert info["path"] == ("manifold" if mesh == "spot" else "tufted")


def test_laplacian_paths_and_info():
    V, F = ifem.read_mesh(test_data("spot.obj"))
    L, M, info = ifem.laplacian(V, F, return_info=True)
    assert info["path"] == "manifold" and info["flips"] > 0
    Lt, Mt, info_t = ifem.laplacian(V, F, path="tufted", return_info=True)
    assert info_t["path"] == "tufted"
    # the tufted cover of a manifold mesh is two copies glued back to back: the same operator
    assert abs(Lt - L).max() <= 1e-9 * abs(L).max()
    assert abs(Mt - M).max() <= 1e-12 * abs(M).max()
    L0, _ = ifem.laplacian(V, F, intrinsic_delaunay=False)
    off = L0 - scipy.sparse.diags(L0.diagonal())
    assert off.max() > 0  # spot has obtuse pairs: the plain cotan Laplacian has negative weights


def test_flat_poisson_is_exact_for_linear_functions():
    # On a flat jittered grid, L u = 0 in the interior for any linear u (P1 elements reproduce
    # linear functions), whatever the triangulation; the IDT changes nothing about that.
    n = 11
    V, F = flat_grid(n, jitter=0.3, seed=3)
    j, i = np.divmod(np.arange(len(V)), n + 1)
    interior = (i > 0) & (i < n) & (j > 0) & (j < n)
    L, M = ifem.laplacian(V, F)
    u = 2.0 * V[:, 0] - 3.0 * V[:, 1]
    r = L @ u
    assert abs(r[interior]).max() < 1e-12
    assert abs(M.diagonal().sum() - 1.0) < 1e-12  # total area of the unit square


def test_point_cloud_laplacian_matches_cli(tmp_path):
    V, F = ifem.read_mesh(test_data("spot.obj"))
    P = V[::2].copy()
    for k in (8, 30):
        L, M = ifem.point_cloud_laplacian(P, k=k)
        assert_laplacian_invariants(L, M, len(P))
        xyz = tmp_path / "p.xyz"
        np.savetxt(xyz, P, fmt="%.17g")
        run_cli("laplacian", xyz, "--knn", k, "-o", tmp_path / f"pc{k}", "--quiet")
        Lc = read_matrix_market(tmp_path / f"pc{k}_L.mtx")
        assert abs(L - Lc).max() <= 1e-12 * abs(Lc).max()
    # the k actually matters
    L8, _ = ifem.point_cloud_laplacian(P, k=8)
    L30, _ = ifem.point_cloud_laplacian(P, k=30)
    assert abs(L8 - L30).max() > 1e-3 * abs(L30).max()
