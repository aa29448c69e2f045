"""`ifem poisson`: every integer and real option given a value that does not fit fails with exit
code 2 and one line naming the option, the value and the allowed range (badvalues.py)."""

import pytest

from badvalues import bad_value_cases, case_id, check_bad_value

CASES = bad_value_cases(['poisson'])


@pytest.mark.parametrize("case", CASES, ids=[case_id(c) for c in CASES])
def test_bad_value(cli, case):
    check_bad_value(cli, *case)
