"""The bad option values of test_cli_values_*.py. The command line cannot break the tool: every
integer and real option of every command, given a value that does not fit (2^31, 2^32+2), is negative, overflows a double (1e400), is not a
finite number (nan, inf), is empty or is not a number, fails with exit code 2 and one line
naming the option, the value and the allowed range (before the input is even read)."""

import re

INT_FAMILY = ["2147483648", "4294967298", "-1", "1e400", "nan", "abc", "3x", ""]
REAL_FAMILY = ["-1", "1e400", "nan", "inf", "abc", "3x", ""]
SURFACE_INTS = ["--knn"]
SURFACE_REALS = ["--mollify"]
REFINE_INTS = ["--max-insertions", "--relax"]
REFINE_REALS = ["--min-angle", "--resolution", "--max-area", "--max-edge"]

# per command: the arguments it needs to get past its own checks, its integer and real options
# (each command but geodesic also takes the shared surface options; geodesic has its own
# --mollify and no --knn)
ARGS = {
    "info": [],
    "laplacian": ["-o", "argtest"],
    "distance": ["--source", "0", "-o", "argtest.txt"],
    "eigen": ["-o", "argtest.ply"],
    "poisson": ["-o", "argtest.txt"],
    "refine": ["-o", "argtest.ply"],
    "geodesic": ["--path", "0,1", "-o", "argtest.obj"],
}
INTS = {
    "info": SURFACE_INTS,
    "laplacian": SURFACE_INTS,
    "distance": ["--correction-steps"] + REFINE_INTS + SURFACE_INTS,
    "eigen": ["-k"] + REFINE_INTS + SURFACE_INTS,
    "poisson": REFINE_INTS + SURFACE_INTS,
    "refine": REFINE_INTS + SURFACE_INTS,
    "geodesic": ["--bezier"],
}
REALS = {
    "info": SURFACE_REALS,
    "laplacian": SURFACE_REALS,
    "distance": ["--time-factor"] + REFINE_REALS + SURFACE_REALS,
    "eigen": REFINE_REALS + SURFACE_REALS,
    "poisson": ["--screening"] + REFINE_REALS + SURFACE_REALS,
    "refine": REFINE_REALS + SURFACE_REALS,
    "geodesic": ["--mollify"],
}


def bad_value_cases(commands=None):
    """(command, option, value, base arguments) for `commands` (default: all), then the
    vertex-id cases (--source of distance, --all-from of geodesic) of those commands."""
    commands = list(ARGS) if commands is None else commands
    cases = []
    for cmd in commands:
        for options, family in ((INTS[cmd], INT_FAMILY), (REALS[cmd], REAL_FAMILY)):
            for option in options:
                for value in family:
                    cases.append((cmd, option, value, ARGS[cmd]))
    # vertex ids: the same family for --source and --all-from (each without its own base)
    for value in ["4294967296", "2147483648", "-1", "1e400", "nan", "abc", "3x", "0,,1", ""]:
        if "distance" in commands:
            cases.append(("distance", "--source", value, ["-o", "argtest.txt"]))
        if "geodesic" in commands:
            cases.append(("geodesic", "--all-from", value, ["-o", "argtest.txt"]))
    return cases


def check_bad_value(cli, cmd, option, value, base):
    """exit 2, the message names OPTION 'VALUE' and a range; an empty value given as --name="""
    if value == "":
        given = ["--k=" if option == "-k" else f"{option}="]
    else:
        given = [option, value]
    cli.fails(rf"{re.escape(option)} '{re.escape(value)}': .*; expected .*[\[(]", cmd, cli.spot,
              *base, *given, "--quiet", rc=2)


def case_id(case):
    cmd, option, value, _ = case
    return f"{cmd} {option} '{value}'"
