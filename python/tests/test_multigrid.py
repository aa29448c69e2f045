"""The ``solver=`` keyword of distance, HeatDistanceSolver and poisson (the CLI's --solver):
auto is the direct solver here, multigrid (on the hierarchy of intrinsic simplifications) gives
the direct solver's answers, and a bad name is refused naming the argument."""

import numpy as np
import pytest

import ifem
from conftest import test_data


@pytest.fixture(scope="module")
def spot():
    return ifem.read_mesh(test_data("spot.obj"))


def test_auto_equals_direct(spot):
    V, F = spot
    assert np.array_equal(ifem.distance(V, F, 0, solver="auto"), ifem.distance(V, F, 0))
    bc = {0: 1.0, 657: -1.0}
    assert np.array_equal(ifem.poisson(V, F, dirichlet=bc, solver="auto"),
                          ifem.poisson(V, F, dirichlet=bc))


def test_multigrid_equals_direct(spot):
    V, F = spot
    bc = {0: 1.0, 657: -1.0}
    ua = ifem.poisson(V, F, dirichlet=bc)
    ub = ifem.poisson(V, F, dirichlet=bc, solver="multigrid")
    assert np.abs(ua - ub).max() <= 1e-6 * np.abs(ua).max()
    # distances: the iterative heat takes continuation stages (D-231, D-285), so it differs by
    # the order of the method's own error; against the exact distance it is as accurate
    da, db = ifem.distance(V, F, 0), ifem.distance(V, F, 0, solver="multigrid")
    exact = np.asarray(ifem.exact_distance(V, F, [0]))
    ea, eb = np.abs(da - exact), np.abs(db - exact)
    assert eb.mean() <= 1.1 * ea.mean() + 1e-3
    assert eb.max() <= 1.1 * ea.max() + 1e-3


def test_bad_solver_name(spot):
    V, F = spot
    for call in (lambda: ifem.distance(V, F, 0, solver="cg"),
                 lambda: ifem.poisson(V, F, solver="cholesky")):
        with pytest.raises(ifem.InvalidInput, match="solver must be"):
            call()
