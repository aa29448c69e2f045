"""The `ifem` command-line tool end to end: shared fixtures and checks.

CMake (tests/cli/CMakeLists.txt) runs one pytest per test file with these variables set:

  IFEM_EXE          the `ifem` binary (required: a run without it is an error, never a skip)
  IFEM_TEST_DATA    tests/data of the source tree (required)
  IFEM_SHARED_DATA  ../shared/data (optional: only the tests that need it skip when absent)
  IFEM_EXAMPLE_HEAT_DISTANCE  examples/example_heat_distance (required by test_cli_examples.py)

Every check here fails loudly: a command that should fail must exit non-zero (or with the exact
code asked for), its last stderr line must match the expected message, and no output file (nor
its `.tmp`) may be left behind.
"""

import os
import pathlib

import pytest

from clitools import Cli


def _required_path(name, *, executable=False):
    value = os.environ.get(name)
    if not value:
        raise pytest.UsageError(
            f"{name} is not set: these tests run through ctest (tests/cli/CMakeLists.txt), "
            f"or set {name} by hand")
    path = pathlib.Path(value)
    if not path.exists():
        raise pytest.UsageError(f"{name}={value}: no such file or directory")
    if executable and not os.access(path, os.X_OK):
        raise pytest.UsageError(f"{name}={value}: not executable")
    return path


def pytest_configure(config):
    # Checked before collection, so a run without the binary or the data stops with an error
    # (pytest exit code 4) instead of skipping everything and passing.
    _required_path("IFEM_EXE", executable=True)
    _required_path("IFEM_TEST_DATA")


@pytest.fixture
def cli(tmp_path):
    return Cli(_required_path("IFEM_EXE", executable=True), _required_path("IFEM_TEST_DATA"),
               tmp_path)


@pytest.fixture
def shared_data():
    """../shared/data, or a skip when it is absent (the only skip these tests make)."""
    value = os.environ.get("IFEM_SHARED_DATA")
    if not value or not pathlib.Path(value, "meshes").is_dir():
        pytest.skip(f"../shared/data is absent ({value})")
    return pathlib.Path(value)
