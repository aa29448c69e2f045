"""ifem.exact_distance: the exact reference of tests/data (1e-9 relative), Euclidean distance on
a flat grid, paths whose length is the distance, the memory budget and bad arguments."""

import numpy as np
import pytest

import ifem
from conftest import flat_grid, test_data


def test_reference_and_paths():
    ref = np.loadtxt(test_data("reference/bunny_npm_lowres.src0.exact.txt"))
    d, paths, info = ifem.exact_distance(str(test_data("bunny_npm_lowres.obj")), sources=[0],
                                         paths_from=[5, 700, 1500], return_info=True)
    m = ref > 0
    assert np.max(np.abs(d[m] - ref[m]) / ref[m]) <= 1e-9
    assert info["windows"] > 0
    for v, p in zip([5, 700, 1500], paths):
        length = np.linalg.norm(np.diff(p, axis=0), axis=1).sum()
        assert abs(length - d[v]) <= 1e-9 * d[v]
        assert np.allclose(p[-1], p[-1])  # the source: vertex 0
    V = np.loadtxt(test_data("bunny_npm_lowres.obj"), usecols=(1, 2, 3),
                   comments=("#", "f", "vn", "vt", "o", "g", "s", "m", "u"))
    assert np.allclose(paths[0][0], V[5]) and np.allclose(paths[0][-1], V[0])


def test_flat_is_euclidean():
    V, F = flat_grid(12)
    d = ifem.exact_distance(V, F, sources=[7])
    assert np.max(np.abs(d - np.linalg.norm(V - V[7], axis=1))) <= 1e-12


def test_budget_and_bad_arguments():
    V, F = flat_grid(12)
    with pytest.raises(ifem.InvalidInput, match="more than .* windows"):
        ifem.exact_distance(V, F, sources=[0], memory_budget=1e-7)
    with pytest.raises(ifem.InvalidInput):
        ifem.exact_distance(V, F, sources=[len(V)])
    with pytest.raises(ifem.InvalidInput):
        ifem.exact_distance(V, F, sources=[0], memory_budget=-1)
    with pytest.raises(ifem.InvalidInput):
        ifem.exact_distance(V, F, sources=[0], refine=True, paths_from=[1])


def test_zero_area_faces_are_crossed():
    # as tests/cli/test_cli_exact.py: four coincident copies of an interior point joined by
    # zero-area faces; every copy is 2 from the apex (the default margin, D-350; 0 fails)
    V = np.array([[0, 0, 0], [3, 0, 0], [1.5, 3, 0]] + [[1.5, 1, 0]] * 4, float)
    F = np.array([[0, 1, 3], [1, 4, 3], [0, 3, 5], [3, 4, 6], [4, 5, 6], [5, 3, 6], [1, 2, 4],
                  [0, 5, 2], [5, 4, 2]])
    d = ifem.exact_distance(V, F, [2])
    assert np.abs(d[3:] - 2.0).max() <= 1e-11
    assert not np.allclose(ifem.exact_distance(V, F, [2], mollify=0.0)[3:], 2.0, atol=1e-6)

