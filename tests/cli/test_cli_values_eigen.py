"""`ifem eigen`: every integer and real option given a value that does not fit fails with exit
code 2 and one line naming the option, the value and the allowed range (badvalues.py)."""

import pytest

from badvalues import bad_value_cases, case_id, check_bad_value

CASES = bad_value_cases(['eigen'])


@pytest.mark.parametrize("case", CASES, ids=[case_id(c) for c in CASES])
def test_bad_value(cli, case):
    check_bad_value(cli, *case)


def test_coarse_prints_an_approximation_with_residuals(cli):
    r = cli.ok("eigen", cli.spot, "-k", "4", "--coarse", "500", "-o", "e.ply", "--quiet")
    assert "approximation (spectral coarsening to 500 vertices, 0 block iterations)" in r.out
    residuals = r.out.split("lambda M phi||:")[1].split()
    assert len(residuals) == 4 and all(float(x) >= 0 for x in residuals)


def test_coarse_iterations_need_coarse(cli):
    cli.refuse(2, "--coarse-iterations needs --coarse N", cli.out / "e.ply", "eigen", cli.spot,
               "--coarse-iterations", "2")


def test_coarse_not_above_k_plus_extra_is_refused(cli):
    cli.refuse(1, "coarse = 12 must be above k \\+ extra_pairs = 16", cli.out / "e.ply", "eigen",
               cli.spot, "-k", "10", "--coarse", "12")
