"""`--solver direct|multigrid|auto` of `ifem distance` and `ifem poisson`: the help teaches it;
auto is the direct solver below its size and without a hierarchy provider (distance); multigrid
is refused with the reason while this build has no provider (poisson; distance: the Python and
library tests); a bad name is a usage error."""

from clitools import numbers


def test_solver_in_help(cli):
    for command in ("distance", "poisson"):
        r = cli.ok(command, "--help")
        assert "--solver KIND" in r.output and "multigrid" in r.output, r.describe()


def test_auto_is_direct_here(cli):
    a, b = cli.out / "d_direct.txt", cli.out / "d_auto.txt"
    cli.ok("distance", cli.spot, "--source", 0, "-o", a, "--quiet")
    cli.ok("distance", cli.spot, "--source", 0, "--solver", "auto", "-o", b, "--quiet")
    assert numbers(a) == numbers(b)


def test_multigrid_refused_without_hierarchy(cli):
    bc = cli.out / "bc1.txt"
    bc.write_text("0 1\n")
    out = cli.out / "u_mg.txt"
    cli.fails_no_partial("no multigrid hierarchy is available", out, "poisson", cli.spot,
                         "--dirichlet", bc, "--solver", "multigrid", "-o", out, "--quiet")


def test_bad_solver_name(cli):
    out = cli.out / "d_bad.txt"
    cli.fails_no_partial("'cg' is not one of direct, multigrid, auto", out, "distance", cli.spot,
                         "--source", 0, "--solver", "cg", "-o", out, "--quiet", rc=2)
