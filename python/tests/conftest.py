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


def run_cli(*args):
    """Runs `ifem ARGS...` and returns its stdout; fails the test on a non-zero exit."""
    r = subprocess.run([cli_path(), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, f"ifem {' '.join(map(str, args))} failed:\n{r.stderr}"
    return r.stdout


def read_txt(path):
    """A .txt result of the CLI: one line per input vertex, one or more columns."""
    return np.loadtxt(path, ndmin=1)


def read_matrix_market(path):
    import scipy.io
    return scipy.io.mmread(str(path)).tocsc()


# test_data is a helper, not a test
test_data.__test__ = False
