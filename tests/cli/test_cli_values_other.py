"""`ifem info`, `laplacian` and `geodesic` (with --all-from): every integer and real option given a
value that does not fit fails with exit code 2 and one line naming the option, the value and
the allowed range (badvalues.py); all commands together make the 329 cases the CMake loops made.
Then the limits that depend on the input, and the shape of the command line."""

import pytest

from badvalues import bad_value_cases, case_id, check_bad_value

CASES = bad_value_cases(['info', 'laplacian', 'geodesic'])


@pytest.mark.parametrize("case", CASES, ids=[case_id(c) for c in CASES])
def test_bad_value(cli, case):
    check_bad_value(cli, *case)


def test_bad_value_count():
    # 311 option/value pairs and 18 vertex-id cases over all commands, as the CMake loops made
    assert len(bad_value_cases()) == 329


# the user's reports: each a clear error with exit 2 (was: vertex 0, a segfault, k = 2)
def test_source_2pow32(cli):
    out = cli.out / "d.txt"
    cli.fails_no_partial(r"--source '4294967296': out of range; expected .*\[0, ", out,
                         "distance", cli.spot, "--source", "4294967296", "-o", out, rc=2)


def test_eigen_k_2pow32(cli):
    out = cli.out / "e.ply"
    cli.fails_no_partial("-k '4294967298': out of range", out, "eigen", cli.spot, "-k",
                         "4294967298", "-o", out, rc=2)


def test_knn_2pow32(cli):
    cli.fails("--knn '4294967298': out of range", "info", cli.spot, "--pointcloud", "--knn",
              "4294967298", rc=2)


# limits that depend on the input, checked right after reading it (exit 2, the limit named)
def test_source_vertex_count(cli):
    cli.fails(r"--source 2930: vertex out of range \[0, 2930\) \(the input has 2930 vertices\)",
              "distance", cli.spot, "--source", "5,2930", "-o", "argtest.txt", "--quiet", rc=2)


def test_eigen_k_vertex_count(cli):
    cli.fails(r"-k 2930: out of range \[1, 2930\)", "eigen", cli.spot, "-k", "2930", "-o",
              "argtest.ply", "--quiet", rc=2)


def test_knn_point_count(cli):
    cli.fails(r"--knn 2930: out of range \[2, 2930\) \(the input has 2930 points\)", "info",
              cli.spot, "--pointcloud", "--knn", "2930", "--quiet", rc=2)


# the shape of the command line: unknown options, missing values, values given to flags,
# options given twice, output extensions checked before any work
SHAPE = [
    ("option -k needs a value", ["eigen", "SPOT", "-o", "argtest.ply", "-k"], 2),
    ("option --output needs a value", ["distance", "SPOT", "--source", "0", "-o", "--quiet"], 2),
    ("option --json takes no value, got '1'", ["info", "SPOT", "--json=1"], 2),
    ("option -k given twice", ["eigen", "SPOT", "-k", "3", "--k", "4", "-o", "argtest.ply"], 2),
    ("unknown option -x", ["info", "SPOT", "-x"], 2),
    ("unknown option --frobnicate", ["distance", "SPOT", "--frobnicate"], 2),
    ("expected one input file MESH, got 2", ["laplacian", "SPOT", "SPOT", "-o", "argtest"], 2),
    ("--output '.*e.txt': the output must end in .ply$", ["eigen", "SPOT", "-o", "OUT/e.txt"], 2),
    ("--mesh 'refined.obj': the output must end in .ply$",
     ["refine", "SPOT", "--mesh", "refined.obj"], 2),
    ("does_not_exist.obj", ["info", "OUT/does_not_exist.obj"], 1),
]


@pytest.mark.parametrize("regex,args,rc", SHAPE, ids=[" ".join(a) for _, a, _ in SHAPE])
def test_command_line_shape(cli, regex, args, rc):
    args = [str(cli.spot) if a == "SPOT" else a.replace("OUT/", f"{cli.out}/") for a in args]
    cli.fails(regex, *args, rc=rc)
