"""Every contract function has trusted checks: the reference passes them all, hostile outputs fail them cleanly,
and every error a contract file promises is a hidden case."""

import re
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

import reference
from grader.checks import all_checks, evaluate, run_hidden_checks, seeded_cases
from grader.checks.base import run_steps
from grader.course_pack import pack
_COURSE = pack("deformation")
CONTRACT_NAMES = _COURSE.function_names
reference_function = _COURSE.reference_function
from grader.harness.outputs import CaseOutput

ROOT = Path(__file__).resolve().parents[2]


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
    must_raise = {f"raises {c.context['raises']}" for c in cases if "raises" in c.context}
    assert result.failed_verdicts() == {"output shape"} | must_raise


def promised_errors() -> dict[str, str]:
    """Contract function -> its table row, for every row of the contract files that asks for a ``ValueError``."""
    found = {}
    # shared/CONTRACT.md sits beside the checkout when there is one (as in tests/grader/test_contract.py)
    for path in (ROOT / "BONUS_CONTRACT.md", ROOT / "LECTURE_CONTRACT.md", ROOT.parent / "shared" / "CONTRACT.md"):
        if not path.exists():
            continue
        for row in path.read_text().splitlines():
            name = re.match(r"\| `(\w+)\(", row)
            if name and "ValueError" in row:
                found[name.group(1)] = row
    return found


def raise_cases(function: str, seed: int = 0):
    return [c for c in seeded_cases(function, seed)[0] if "raises" in c.context]


def test_every_error_a_contract_file_promises_is_a_hidden_case():
    promised = promised_errors()
    assert {"dual_quaternions", "fast_precompute", "tet_arap_precompute"} <= set(promised)
    for function, row in promised.items():
        labels = " / ".join(c.label for c in raise_cases(function))
        assert labels, f"{function}: the contract asks for a ValueError ({row}), no hidden case checks it"
    # each condition the rows name has its own case
    for function, words in {
        "dual_quaternions": ("scaled", "reflection"),
        "fast_precompute": ("no fixed handle", "planar mesh in 3D", "weight column is zero"),
        "tet_arap_precompute": ("no handle", "repeated", "out of range"),
    }.items():
        labels = [c.label for c in raise_cases(function)]
        for word in words:
            assert any(word in label for label in labels), f"{function}: no hidden case for {word!r}: {labels}"


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("function", ["dual_quaternions", "fast_precompute", "tet_arap_precompute"])
def test_the_reference_raises_a_plain_value_error_on_every_raise_case(function, seed):
    for case in raise_cases(function, seed):
        with pytest.raises(ValueError) as caught:
            run_steps(case, reference_function)
        assert type(caught.value) is ValueError, f"{case.label}: {type(caught.value).__name__}"


@pytest.mark.parametrize("function", ["dual_quaternions", "fast_precompute", "tet_arap_precompute"])
def test_a_raise_case_passes_only_a_value_error(function):
    cases, expected = seeded_cases(function, 0)
    checks = all_checks()[function]
    must = [i for i, c in enumerate(cases) if "raises" in c.context]
    for recorded, passes in (
        (CaseOutput(None, "ValueError: T[1] is not rigid (line 7)", 0.1), True),
        (CaseOutput(None, "LinAlgError: 3-th leading minor of the array is not positive definite", 0.1), False),
        (CaseOutput(None, "RuntimeError: Factor is exactly singular", 0.1), False),
        (CaseOutput(np.zeros((2, 2, 4)), None, 0.1), False),  # returned a result
        (CaseOutput(None, "output could not be read: returned a SimpleNamespace, which is not a numeric array", 0.1), False),
    ):
        outputs = [recorded if i in must else CaseOutput(None, "skipped", 0.0) for i in range(len(cases))]
        result = evaluate(checks, cases, outputs, expected)
        verdicts = [result.cases[i].verdicts for i in must]
        assert all(len(v) == 1 and v[0].passed == passes for v in verdicts), (recorded, verdicts)
        if not passes:
            detail = verdicts[0][0].detail
            assert ("returned a result" in detail) if recorded.error is None or recorded.error.startswith("output") else \
                (recorded.error.split(":")[0] in detail and "not ValueError" in detail), detail
