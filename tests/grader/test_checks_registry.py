"""Every contract function has trusted checks: the reference passes them all, hostile outputs fail them cleanly."""

import numpy as np
import pytest
import scipy.sparse as sp

import reference
from grader.checks import all_checks, evaluate, run_hidden_checks, seeded_cases
from grader.contract import CONTRACT_NAMES
from grader.harness.outputs import CaseOutput


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


#: Outputs no contract function may return: each must fail as "output shape", never crash a check.
HOSTILE = {
    "wrong shape": np.zeros((3, 7, 2)),
    "NaN": np.full((5, 3), np.nan),
    "a tuple of three arrays": (np.zeros(3), np.zeros(3), np.zeros(3)),
    "text": np.array("R"),
    "a sparse matrix of the wrong shape": sp.csr_matrix(np.eye(4)),
}


@pytest.mark.parametrize("hostile", HOSTILE)
@pytest.mark.parametrize("function", sorted(CONTRACT_NAMES))
def test_hostile_outputs_fail_with_an_output_shape_verdict(function, hostile):
    cases, expected = seeded_cases(function, 3)
    outputs = [CaseOutput(HOSTILE[hostile], None, None)] * len(cases)
    result = evaluate(all_checks()[function], cases, outputs, expected)
    assert result.fraction == 0.0
    assert result.failed_verdicts() == {"output shape"}
