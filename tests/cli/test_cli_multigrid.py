"""`--solver direct|multigrid|auto` of `ifem distance` and `ifem poisson`: the help teaches it;
auto is the direct solver for distances and below its size; multigrid (on the hierarchy of
intrinsic simplifications) gives the direct solver's answers; a bad name is a usage error."""

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


def test_multigrid_equals_direct(cli):
    bc = cli.out / "bc2.txt"
    bc.write_text("0 1\n657 -1\n")
    a, b = cli.out / "u_direct.txt", cli.out / "u_mg.txt"
    cli.ok("poisson", cli.spot, "--dirichlet", bc, "-o", a, "--quiet")
    cli.ok("poisson", cli.spot, "--dirichlet", bc, "--solver", "multigrid", "-o", b, "--quiet")
    ua, ub = numbers(a), numbers(b)
    assert len(ua) == len(ub) == 2930
    scale = max(abs(x) for x in ua)
    assert max(abs(x - y) for x, y in zip(ua, ub)) <= 1e-6 * scale


def test_bad_solver_name(cli):
    out = cli.out / "d_bad.txt"
    cli.fails_no_partial("'cg' is not one of direct, multigrid, auto", out, "distance", cli.spot,
                         "--source", 0, "--solver", "cg", "-o", out, "--quiet", rc=2)
