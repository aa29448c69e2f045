"""ifem.simplify: the coarse faces, kept vertices and P against the invariants (rows of P ≥ 0
summing to 1, kept vertices interpolated exactly, coarse areas summing to the input's), the
CLI's answer on the same mesh (same kept vertices, same P rows), the Galerkin coarse Laplacian's
smallest eigenvalues on a sphere, the tufted cover, and refusals."""

import math

import numpy as np
import pytest
import scipy.sparse.linalg

import ifem
from conftest import run_cli, test_data


def heron(lengths):
    a, b, c = lengths.T
    s = (a + b + c) / 2
    return np.sqrt(np.maximum(s * (s - a) * (s - b) * (s - c), 0))


def uv_sphere(n):
    """A unit sphere as rings (no pole fans of needles: n rings of 2n vertices + 2 poles)."""
    V = [(0, 0, 1)]
    for i in range(1, n):
        t = math.pi * i / n
        V += [(math.sin(t) * math.cos(2 * math.pi * j / (2 * n)),
               math.sin(t) * math.sin(2 * math.pi * j / (2 * n)), math.cos(t))
              for j in range(2 * n)]
    V.append((0, 0, -1))
    m, F = 2 * n, []
    for j in range(m):
        F.append((0, 1 + j, 1 + (j + 1) % m))
    for i in range(n - 2):
        for j in range(m):
            a, b = 1 + i * m + j, 1 + i * m + (j + 1) % m
            F += [(a, a + m, b + m), (a, b + m, b)]
    last = len(V) - 1
    for j in range(m):
        F.append((last, 1 + (n - 2) * m + (j + 1) % m, 1 + (n - 2) * m + j))
    return np.array(V, float), np.array(F)


def test_invariants_and_area():
    path = test_data("spot.obj")
    V, F = ifem.read_mesh(path)[:2]
    faces, kept, P, info = ifem.simplify(V, F, vertices=300, return_info=True)
    assert faces.shape[1] == 3 and len(kept) == 300 == info["vertices_after"]
    assert len(set(kept.tolist())) == 300
    assert P.shape == (len(V), 300)
    assert abs(P @ np.ones(300) - 1).max() < 1e-12 and P.min() >= 0
    assert np.array_equal(P[kept].toarray(), np.eye(300))
    fine_area = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]),
                                     axis=1).sum()
    assert heron(info["side_lengths"]).sum() == pytest.approx(fine_area, rel=1e-9)


def test_same_as_cli(tmp_path):
    path = test_data("spot.obj")
    faces, kept, P = ifem.simplify(str(path), ratio=0.2)
    run_cli("simplify", str(path), "--ratio", "0.2", "-o", str(tmp_path / "c.ply"), "--ascii",
            "--map", str(tmp_path / "m.txt"), "--quiet")
    rows = np.loadtxt(tmp_path / "m.txt")
    assert rows.shape == (P.shape[0], 6)
    dense = np.zeros(P.shape)
    for i, r in enumerate(rows):
        for k in range(3):
            dense[i, int(r[k])] += r[3 + k]
    assert abs(dense - P.toarray()).max() < 1e-12


def test_galerkin_spectrum_of_a_sphere():
    V, F = uv_sphere(40)  # 3,122 vertices
    _, kept, P = ifem.simplify(V, F, vertices=600)
    L, M = ifem.laplacian(V, F)
    Lc, Mc = (P.T @ L @ P).tocsc(), (P.T @ M @ P).tocsc()
    vals = np.sort(scipy.sparse.linalg.eigsh(Lc, 9, Mc, sigma=-1e-3)[0])
    # unit sphere: 0, 2 (×3), 6 (×5); Galerkin restriction only raises Rayleigh quotients
    assert abs(vals[0]) < 1e-8
    assert vals[1:4] == pytest.approx(2.0, rel=0.03)
    assert vals[4:9] == pytest.approx(6.0, rel=0.03)


def test_tufted_cover():
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0.2], [0.5, 0.1, 1], [1.5, 1, 0],
                  [1.5, -0.5, 0.1], [2, 0.3, 0.2]], float)
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [1, 5, 2], [1, 6, 5], [6, 7, 5]])
    faces, kept, P, info = ifem.simplify(V, F, ratio=0.8, return_info=True)
    assert info["path"] == "tufted" and info["multiplicity"] == 2
    assert abs(P @ np.ones(P.shape[1]) - 1).max() < 1e-12 and P.min() >= 0


@pytest.mark.parametrize("kwargs, regex", [
    ({}, "exactly one"),
    ({"vertices": 10, "ratio": 0.5}, "exactly one"),
    ({"ratio": 0.0}, "exactly one"),
    ({"ratio": 1.5}, "ratio"),
    ({"vertices": 2930}, "target_vertices"),
])
def test_refusals(kwargs, regex):
    with pytest.raises(ifem.InvalidInput, match=regex):
        ifem.simplify(str(test_data("spot.obj")), **kwargs)


def test_tangent_prolongation():
    """P_tangent: P's magnitudes with phases; a flat grid's parallel field stays of unit length."""
    path = test_data("spot.obj")
    V, F = ifem.read_mesh(path)[:2]
    faces, kept, P, Pt, info = ifem.simplify(V, F, vertices=300, tangent=True, return_info=True)
    assert Pt.shape == P.shape and np.iscomplexobj(Pt.data)
    assert abs(abs(Pt).sum(axis=1) - 1).max() < 1e-12
    assert abs(abs(Pt) - P).max() < 1e-12
    assert abs(np.angle(Pt.data)).max() > 0.1  # not the scalar P
    assert ifem.simplify(V, F, vertices=300)[2].shape == P.shape  # default: no P_tangent
