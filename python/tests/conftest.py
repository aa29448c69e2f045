"""Shared fixtures of the Python tests (run by ctest: python/CMakeLists.txt sets PYTHONPATH to
the build's python/ folder, IFEM_CLI to the ifem executable and the data folders)."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

TEST_DATA = pathlib.Path(os.environ.get(
    "IFEM_TEST_DATA", pathlib.Path(__file__).resolve().parents[2] / "tests" / "data"))
SHARED_DATA = pathlib.Path(os.environ.get(
    "IFEM_SHARED_DATA", pathlib.Path(__file__).resolve().parents[3] / "shared" / "data"))


def test_data(name):
    """A file of tests/data (always present)."""
    return TEST_DATA / name


def shared_data(name):
    """A file of ../shared/data; skips the test when it is absent."""
    p = SHARED_DATA / name
    if not p.exists():
        pytest.skip(f"{p} is absent (../shared/data is optional)")
    return p


def cli_path():
    exe = os.environ.get("IFEM_CLI")
    if not exe or not os.path.exists(exe):
        pytest.skip("IFEM_CLI is not set (run the Python tests through ctest)")
    return exe


def run_cli_logged(*args):
    """Runs `ifem ARGS...` and returns (stdout, stderr); fails the test on a non-zero exit."""
    r = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, f"ifem {' '.join(map(str, args))} failed:\n{r.stderr}"
    return r.stdout, r.stderr


def run_cli(*args):
    """Runs `ifem ARGS...` and returns its stdout; fails the test on a non-zero exit."""
    return run_cli_logged(*args)[0]


def read_txt(path):
    """A .txt result of the CLI: one line per input vertex, one or more columns."""
    return np.loadtxt(path, ndmin=1)


def read_matrix_market(path):
    import scipy.io
    return scipy.io.mmread(str(path)).tocsc()


def flat_grid(n, jitter=0.3, seed=7, straight_rows=(), slide_left_right=True):
    """The unit square as (n+1)² vertices in the plane z = 0, interior ones jittered by up to
    jitter/n in x and y; boundary ones slide only along their side (the left and right sides'
    not at all unless slide_left_right), rows in straight_rows only along x (so that they stay
    on a line). Vertex (i, j) is j·(n+1) + i; faces counter-clockwise seen from +z."""
    rng = np.random.default_rng(seed)
    j, i = np.mgrid[0:n + 1, 0:n + 1]
    dx, dy = rng.uniform(-jitter / n, jitter / n, (2,) + i.shape)
    x = i / n + np.where((i > 0) & (i < n), dx, 0)
    move_y = (j > 0) & (j < n) & ~np.isin(j, straight_rows)
    if not slide_left_right:
        move_y &= (i > 0) & (i < n)
    y = j / n + np.where(move_y, dy, 0)
    V = np.c_[x.ravel(), y.ravel(), np.zeros(x.size)]
    a = (j * (n + 1) + i)[:-1, :-1].ravel()
    F = np.r_[np.c_[a, a + 1, a + n + 2], np.c_[a, a + n + 2, a + n + 1]]
    return V, F


def read_obj_polylines(path):
    """The CLI's .obj curves: 'v' lines, one 'l' line per curve (1-based)."""
    v, lines = [], []
    for line in path.read_text().splitlines():
        w = line.split()
        if w and w[0] == "v":
            v.append([float(x) for x in w[1:4]])
        elif w and w[0] == "l":
            lines.append([int(x) - 1 for x in w[1:]])
    v = np.array(v)
    return [v[idx] for idx in lines]


# test_data is a helper, not a test
test_data.__test__ = False
