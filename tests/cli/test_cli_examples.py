"""The README's library example (examples/example_heat_distance.cpp) and `ifem distance` run
the same pipeline: bit-identical distances, plain and with --refine, on spot, on the nonmanifold
fan (tufted path) and on a sliver CAD mesh (block.off from ../shared; skipped without it)."""

import os
import pathlib
import re
import subprocess

import pytest


def example_exe():
    value = os.environ.get("IFEM_EXAMPLE_HEAT_DISTANCE")
    assert value and pathlib.Path(value).is_file(), \
        f"IFEM_EXAMPLE_HEAT_DISTANCE={value!r}: the example binary is required"
    return value


def run_example(*args):
    proc = subprocess.run([example_exe(), *map(str, args)], capture_output=True, timeout=110)
    return proc.returncode, proc.stdout.decode("utf-8", "replace") + \
        proc.stderr.decode("utf-8", "replace")


def test_example_heat_distance(cli):
    rc, output = run_example(cli.spot)
    assert rc == 0, output
    assert re.search(r"manifold path, [0-9]+ flips, L 2930x2930.*max distance from vertex 0: 1\.5",
                     output, re.S), output


@pytest.mark.parametrize("refine", [False, True], ids=["plain", "refine"])
@pytest.mark.parametrize("case", ["spot", "fan3", "block"])
def test_example_matches_cli(cli, request, case, refine):
    if case == "block":
        mesh = request.getfixturevalue("shared_data") / "meshes" / "block.off"
        assert mesh.is_file(), f"{mesh} is missing from ../shared/data"
    else:
        mesh = cli.data / f"{case}.obj"
    flag = ["--refine"] if refine else []
    from_cli, from_example = cli.out / "cli.txt", cli.out / "example.txt"
    cli.ok("distance", mesh, "--source", 0, *flag, "-o", from_cli, "--quiet")
    rc, output = run_example(mesh, *flag, from_example)
    assert rc == 0, output
    assert from_cli.read_bytes() == from_example.read_bytes(), "not bit-identical"
