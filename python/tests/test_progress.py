"""Progress of long calls (``progress=callable``): each long stage is reported as fractions that
start at 0, never go down, stay in [0, 1] and end at exactly 1; without a callable nothing is
printed; a bad argument is refused; an exception raised by the callable reaches the caller."""

import numpy as np
import pytest

import ifem
from conftest import flat_grid, test_data


class Recorder:
    def __init__(self):
        self.calls = []

    def __call__(self, fraction, stage):
        assert isinstance(fraction, float) and isinstance(stage, str)
        self.calls.append((fraction, stage))

    def stage(self, name):
        return [f for f, s in self.calls if s == name]


def well_formed(f):
    assert len(f) >= 2
    assert f[0] == 0.0 and f[-1] == 1.0
    assert all(0.0 <= x <= 1.0 for x in f)
    assert all(b >= a for a, b in zip(f, f[1:]))
    assert all(x < 1.0 for x in f[:-1])


def spot():
    return ifem.read_mesh(test_data("spot.obj"))


def test_refine_reports_insertions_and_keeps_its_result():
    V, F = spot()
    r = Recorder()
    a = ifem.refine(V, F, resolution=0.7, progress=r)
    b = ifem.refine(V, F, resolution=0.7)
    assert a.n_vertices == b.n_vertices > V.shape[0] + 100
    f = r.stage("refine")
    well_formed(f)
    assert len(f) > 20  # along the way, not only 0 and 1
    assert {s for _, s in r.calls} == {"refine"}


def test_batched_distances_report_blocks():
    V, F = flat_grid(30)
    solver = ifem.HeatDistanceSolver(V, F)
    sources = np.arange(0, 100 * 7, 7)  # 100 sources: blocks of up to 32
    r = Recorder()
    d = solver.compute_distances(sources, progress=r)
    np.testing.assert_array_equal(d, solver.compute_distances(sources))
    f = r.stage("heat distances")
    well_formed(f)
    # the path bounds (on by default) take the second half of the bar
    assert f[1] == pytest.approx(32 / 200)


def test_eigen_and_single_source_and_read_report_their_stages():
    V, F = spot()
    r = Recorder()
    ifem.eigen(V, F, k=6, refine=True, resolution=1.0, progress=r)
    well_formed(r.stage("refine"))
    well_formed(r.stage("eigenpairs"))
    assert [s for _, s in r.calls].index("eigenpairs") > [s for _, s in r.calls].index("refine")
    V2, F2 = flat_grid(10)
    g = Recorder()
    ifem.single_source_geodesics(V2, F2, 0, progress=g)
    well_formed(g.stage("single-source geodesics"))
    rd = Recorder()
    ifem.read_mesh(test_data("spot.obj"), progress=rd)
    well_formed(rd.stage("read"))
    well_formed(rd.stage("parse"))
    pr = Recorder()
    ifem.poisson(V2, F2, np.ones(V2.shape[0]), {0: 0.0}, refine=True, resolution=0.5, progress=pr)
    well_formed(pr.stage("refine"))


def test_nothing_printed_without_a_callable(capfd):
    V, F = spot()
    ifem.refine(V, F, resolution=0.7)
    ifem.HeatDistanceSolver(V, F).compute_distances([0, 1, 2])
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_bad_progress_is_refused_and_exceptions_reach_the_caller():
    V, F = spot()
    with pytest.raises(ifem.InvalidInput, match="progress"):
        ifem.refine(V, F, resolution=0.7, progress=42)

    def stop(fraction, stage):
        if fraction > 0.2:
            raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        ifem.refine(V, F, resolution=0.5, progress=stop)
    with pytest.raises(ifem.InvalidInput, match="progress"):
        ifem.geodesic(V, F, points=[0, 5], progress=stop)
