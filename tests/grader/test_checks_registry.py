"""Every contract function has trusted checks, and the reference passes all of them."""

import pytest

import reference
from grader.checks import all_checks, run_hidden_checks
from grader.contract import CONTRACT_NAMES


def test_every_contract_function_has_described_checks():
    checks = all_checks()
    assert set(checks) == set(CONTRACT_NAMES)
    assert all(c.function == name and c.description for name, c in checks.items())
    assert all(set(c.needs) <= CONTRACT_NAMES for c in checks.values())


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("function", sorted(CONTRACT_NAMES))
def test_the_reference_passes_every_hidden_case(function, seed):
    result = run_hidden_checks(function, dict(vars(reference)), seed)
    assert result.fraction == 1.0 and len(result.cases) >= 4
