"""`ifem eigen`, `ifem poisson` and `ifem refine`: results checked against what must hold
(ascending eigenvalues with a zero first, the maximum principle, the angle bound reached), and
their refusals (exit code, the message, no partial output)."""

import re

from clitools import SPOT_VERTICES, count_lines, grep, head_bytes, lines, numbers


def check_eigenvalues(path, k):
    """k eigenvalues, ascending, the first ≈ 0 (one component)."""
    values = numbers(path)
    assert len(values) == k, values
    assert abs(values[0]) <= 1e-8, values
    assert all(b >= a for a, b in zip(values, values[1:])), values


def test_eigen(cli):
    r = cli.ok("eigen", cli.spot, "-k", 6, "-o", cli.out / "spot_modes.ply", "--quiet")
    check_eigenvalues(cli.out / "spot_modes.eigenvalues.txt", 6)
    assert grep("eigenvalues: [-0-9.e]+ ", r.output), r.describe()


def test_eigen_refine(cli):
    cli.ok("eigen", cli.spot, "-k", 4, "--refine", "-o", cli.out / "spot_modes_r.ply", "--quiet")
    check_eigenvalues(cli.out / "spot_modes_r.eigenvalues.txt", 4)


def test_eigen_bad_k(cli):
    bad = cli.out / "bad_modes.ply"
    cli.fails_no_partial(r"-k '0': out of range; expected an integer in \[1, ", bad, "eigen",
                         cli.spot, "-k", 0, "-o", bad, "--quiet", rc=2)


def check_harmonic(path):
    """Dirichlet data 1 at vertex 0 and -1 at 657 kept; the solution within [-1, 1]."""
    assert count_lines(path) == SPOT_VERTICES
    text = lines(path)
    assert text[0] == "1"
    assert text[657] == "-1"
    for v in numbers(path):
        assert -1 - 1e-9 <= v <= 1 + 1e-9, v


# poisson: Dirichlet data and a right-hand side written at test time; the harmonic solution
# keeps its boundary values and stays between them (maximum principle), refined too
def test_poisson(cli):
    bc = cli.out / "bc.txt"
    bc.write_text("# vertex value\n0 1\n657 -1\n")
    cli.ok("poisson", cli.spot, "--dirichlet", bc, "-o", cli.out / "spot_u.txt", "--quiet")
    check_harmonic(cli.out / "spot_u.txt")
    cli.ok("poisson", cli.spot, "--dirichlet", bc, "--refine", "-o", cli.out / "spot_u_r.txt",
           "--quiet")
    check_harmonic(cli.out / "spot_u_r.txt")
    rhs = cli.out / "rhs.txt"
    rhs.write_text("".join(f"{i % 7 - 3}\n" for i in range(SPOT_VERTICES)))
    cli.ok("poisson", cli.spot, "--rhs", rhs, "--refine", "-o", cli.out / "spot_rhs.ply",
           "--quiet")


def test_poisson_bad_dirichlet(cli):
    bc, bad = cli.out / "bc_bad.txt", cli.out / "bad_u.txt"
    bc.write_text("0 1\n2930 2\n")
    r = cli.run("poisson", cli.spot, "--dirichlet", bc, "-o", bad)
    assert r.rc != 0, r.describe()
    assert grep(r"bc_bad.txt:2: vertex 2930 out of range", r.err), r.describe()
    assert not bad.exists()
    short = cli.out / "rhs_short.txt"
    short.write_text("1\n2\n")
    r = cli.run("poisson", cli.spot, "--rhs", short, "--refine", "-o", bad)
    assert r.rc != 0, r.describe()
    assert grep("expected one per input vertex", r.err), r.describe()
    assert not bad.exists()


def test_poisson_refine_tufted(cli):
    bad = cli.out / "bad_fan.txt"
    cli.fails_no_partial("tufted path.*without signposts", bad, "poisson", cli.fan3, "--refine",
                         "-o", bad, "--quiet")


# poisson's --dirichlet file: a malformed line is an error at file:line, never skipped
def test_poisson_dirichlet_malformed(cli):
    bc, bad = cli.out / "bc_malformed.txt", cli.out / "bad_m.txt"
    for line in ["zero one", "0", "0 1 2", "0 nan", "1.5 2", "3x 1", "0 1e400"]:
        bc.write_text(f"# bc\n\n0 1\n{line}\n")
        bad.unlink(missing_ok=True)
        r = cli.run("poisson", cli.spot, "--dirichlet", bc, "-o", bad, "--quiet")
        assert r.rc != 0, f"accepted: {line}\n" + r.describe()
        assert grep(r"bc_malformed\.txt:4: expected 'vertex value'.*got '" + re.escape(line) +
                    "'", r.err), r.describe()
        assert not bad.exists()


# A right-hand side with a non-finite value is refused with the value's place (issue 10: no
# silent NaN in outputs), exit 1 and no output file.
def test_poisson_rhs_nan(cli):
    rhs, bad = cli.out / "rhs_nan.txt", cli.out / "u_nan.txt"
    rhs.write_text("1\nnan\n" + "0\n" * (SPOT_VERTICES - 2))
    r = cli.run("poisson", cli.spot, "--rhs", rhs, "-o", bad, "--quiet")
    assert r.rc != 0, r.describe()
    assert grep(r"value 2 \(vertex 1\) is nan", r.err), r.describe()
    assert not bad.exists()


# refine: the minimum angle reaches the bound; common subdivision, line set, saved file
def test_refine(cli):
    o = cli.out
    r = cli.ok("refine", cli.spot, "--min-angle", 28, "-o", o / "spot_cs.ply", "--lines",
               o / "spot_lines.ply", "--save", o / "spot.ifem", "--quiet")
    angles = re.findall(r"([0-9.]+)° refined", r.out)
    assert angles and float(angles[0]) >= 28, r.describe()
    assert grep("property int intrinsic_face", head_bytes(o / "spot_cs.ply", 1000))
    assert lines(o / "spot.ifem")[0] == "ifem-integer 1"  # the default correspondence (D-330)


# relaxation with long-edge splits: more vertices than refinement alone
def test_refine_relax_split(cli):
    mesh = cli.out / "spot_relaxed.ply"
    r = cli.ok("refine", cli.spot, "--relax", 2, "--max-edge", 0.02, "--mesh", mesh, "--quiet")
    splits = re.findall(r"([0-9]+) edge splits", r.out)
    assert splits and int(splits[0]) > 0, r.describe()
    assert grep("property double inserted", head_bytes(mesh, 400))


def test_refine_max_edge_needs_relax(cli):
    bad = cli.out / "bad_cs.ply"
    cli.fails_no_partial("--max-edge splits during --relax", bad, "refine", cli.spot,
                         "--max-edge", 0.02, "-o", bad, "--quiet", rc=2)


def test_refine_tufted(cli):
    bad = cli.out / "bad_cs.ply"
    cli.fails_no_partial("tufted path.*without signposts", bad, "refine", cli.fan3, "-o", bad,
                         "--quiet")


def test_refine_bad_angle(cli):
    bad = cli.out / "bad_cs.ply"
    cli.fails_no_partial(r"--min-angle '40': out of range; expected .* \(0, 30\]", bad,
                         "refine", cli.spot, "--min-angle", 40, "-o", bad, "--quiet", rc=2)
