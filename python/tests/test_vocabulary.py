"""One vocabulary (README, "One name per operation"): the README's name table against the
three forms. Fails when an operation is a CLI command but not a Python function (or the other
way round), when the table names something that does not exist, when a deprecated Python name
is not the same function as the new one, when a C++ recipe of the operation's name is not
declared, and when a neighbour count is called anything but ``knn``."""

import inspect
import pathlib
import re
import subprocess

import pytest

import ifem
from conftest import cli_path

ROOT = pathlib.Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
CXX_HEADERS = [ROOT / "solvers" / "recipes" / "recipes.h", ROOT / "solvers" / "recipes" / "geodesic.h",
               ROOT / "solvers" / "recipes" / "isolines.h"]
HEADER = ["operation", "CLI", "Python", "C++"]


def name_table():
    """{operation: {'CLI': cell, 'Python': cell, 'C++': cell}} from the README."""
    lines = README.read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells == HEADER:
            break
    else:
        pytest.fail(f"{README}: no table with the header | {' | '.join(HEADER)} |")
    rows = {}
    for line in lines[i + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        assert len(cells) == 4, f"README name table: 4 cells expected in {line!r}"
        assert cells[0] not in rows, f"README name table: {cells[0]} twice"
        rows[cells[0]] = dict(zip(HEADER[1:], cells[1:]))
    assert rows, "README name table is empty"
    return rows


def helpers():
    """The Python names listed under 'Helpers (not operations):' in the README."""
    text = README.read_text(encoding="utf-8")
    m = re.search(r"Helpers \(not operations\):(.*?)(?:\n\n|$)", text, re.S)
    assert m, "README: no 'Helpers (not operations):' sentence after the name table"
    return set(re.findall(r"`ifem\.(\w+)`", m.group(1)))


def cli_commands():
    """The commands `ifem --help` lists (indented lines after a 'commands' heading), each
    checked to answer `ifem COMMAND --help`."""
    exe = cli_path()
    out = subprocess.run([exe, "--help"], capture_output=True, text=True, check=True).stdout
    commands, inside = [], False
    for line in out.splitlines():
        if re.match(r"^\s*(sub)?commands\s*:?\s*$", line, re.I):
            inside = True
            continue
        if inside:
            if not line.strip():
                if commands:
                    break
                continue
            m = re.match(r"^\s+([a-z][a-z0-9_-]*)\b", line)
            if not m:
                break
            commands.append(m.group(1))
    assert commands, f"no commands found in `ifem --help`:\n{out}"
    for c in commands:
        r = subprocess.run([exe, c, "--help"], capture_output=True, text=True)
        assert r.returncode == 0, f"`ifem {c} --help` failed: {r.stderr}"
    return set(commands)


def test_every_cli_command_has_a_python_function_and_a_row():
    table = name_table()
    commands = cli_commands()
    assert set(table) == commands, (
        f"CLI commands without a README row: {sorted(commands - set(table))}; rows without a "
        f"CLI command: {sorted(set(table) - commands)}")
    for op, row in table.items():
        assert f"`ifem {op}`" in row["CLI"], f"row {op}: the CLI cell must name `ifem {op}`"
        assert row["Python"].startswith(f"`ifem.{op}`"), (
            f"row {op}: the Python cell must start with `ifem.{op}` (the same name)")
        assert op in ifem.__all__, f"ifem.{op} is not in ifem.__all__ (CLI command `ifem {op}`)"
        assert callable(getattr(ifem, op)), f"ifem.{op} is not callable"


def test_every_python_operation_is_in_the_table():
    """A public Python function that is neither in the table nor a listed helper is an
    operation the CLI lacks (or a name the README does not explain)."""
    table = name_table()
    named = set()
    for row in table.values():
        named |= set(re.findall(r"`ifem\.(\w+)`", row["Python"]))
    for name in named:
        assert name in ifem.__all__, f"README names ifem.{name}, which ifem.__all__ lacks"
    known = named | helpers()
    functions = {n for n in ifem.__all__ if inspect.isfunction(getattr(ifem, n))}
    assert functions <= known, (
        f"Python functions in no row of the README's name table (an operation the CLI lacks?): "
        f"{sorted(functions - known)}")


def test_deprecated_names_are_the_same_functions():
    for op, row in name_table().items():
        for old in re.findall(r"deprecated: `ifem\.(\w+)`", row["Python"]):
            assert getattr(ifem, old) is getattr(ifem, op), (
                f"ifem.{old} (deprecated) must be ifem.{op} itself, not a second implementation")
    assert ifem.VectorHeatSolver.log_map is ifem.VectorHeatSolver.logmap


def test_every_operation_has_a_cxx_recipe_of_its_name():
    headers = "\n".join(h.read_text(encoding="utf-8") for h in CXX_HEADERS)
    assert "namespace ifem::recipes" in headers
    for op, row in name_table().items():
        assert row["C++"] == f"`recipes::{op}`", f"row {op}: the C++ cell must be `recipes::{op}`"
        assert re.search(rf"\b{op}\(", headers), f"recipes::{op} is not declared in {CXX_HEADERS}"


def test_neighbour_counts_are_called_knn():
    """`knn` everywhere; `k` only as eigen's number of pairs or a deprecated keyword alias."""
    for name in ifem.__all__:
        obj = getattr(ifem, name)
        if not inspect.isfunction(obj) and not inspect.isclass(obj):
            continue
        fn = obj.__init__ if inspect.isclass(obj) else obj
        try:
            params = inspect.signature(fn).parameters
        except (TypeError, ValueError):
            continue
        for alias in ("k", "n_neighbors", "neighbors", "n_neighbours"):
            if alias not in params or name == "eigen":
                continue
            p = params[alias]
            assert "knn" in params and p.kind == p.KEYWORD_ONLY and p.default is None, (
                f"ifem.{name}: the neighbour count is `knn` ({alias!r} only as a deprecated "
                "keyword-only alias defaulting to None)")


def test_point_cloud_laplacian_takes_the_old_k_too():
    import numpy as np
    P = np.random.default_rng(3).normal(size=(60, 3))
    L1, _ = ifem.point_cloud_laplacian(P, knn=8)
    L2, _ = ifem.point_cloud_laplacian(P, k=8)
    assert abs(L1 - L2).max() == 0
    with pytest.raises(ifem.InvalidInput, match="not both"):
        ifem.point_cloud_laplacian(P, knn=10, k=8)
