"""A common mistake makes the public tests fail with a message that names it."""

import pytest

from grader.corpus import load_entry
from tests.grader.public_hints_audit import BUGGY, HINTS, hinted, public_failures

TRANSPOSED_ROTATION = '''
import numpy as np


def optimal_rotation(S):
    U_tilde, _, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    D = np.ones(U_tilde.shape[:-1])
    D[..., -1] = np.linalg.det(U_tilde @ V_tilde_T)
    return (U_tilde * D[..., None, :]) @ V_tilde_T  # Ũ D Ṽᵀ: the transpose of the answer
'''

TRANSPOSED_ORTHOGONAL = '''
import numpy as np


def optimal_orthogonal(S):
    U_tilde, _, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    return U_tilde @ V_tilde_T
'''

LARGEST_FLIPPED = '''
import numpy as np


def optimal_rotation(S):
    U_tilde, _, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    V_tilde = np.swapaxes(V_tilde_T, -1, -2).copy()
    sign = np.sign(np.linalg.det(V_tilde @ np.swapaxes(U_tilde, -1, -2)))
    V_tilde[..., 0] *= sign[..., None]  # the largest singular value's vector
    return V_tilde @ np.swapaxes(U_tilde, -1, -2)
'''


def public_test_failure(notebook: str, function: str, source: str) -> str:
    """The message of the first failing public test of ``function`` with ``source`` as its solution."""
    found = public_failures(notebook, {function: source}, {function})
    if function not in found:
        raise AssertionError(f"{notebook} has no tests cell for {function}")
    return found[function]


@pytest.mark.parametrize(
    "notebook, function, source, words",
    [
        ("02_sign_correction", "optimal_rotation", TRANSPOSED_ROTATION, ("transpose",)),
        ("01_shape_matching", "optimal_orthogonal", TRANSPOSED_ORTHOGONAL, ("transpose",)),
        ("02_sign_correction", "optimal_rotation", LARGEST_FLIPPED, ("smallest singular value",)),
    ],
    ids=["02 transposed rotation", "01 transposed orthogonal map", "02 flipped the largest singular value"],
)
def test_a_common_mistake_gets_a_hint_that_names_it(notebook, function, source, words):
    message = public_test_failure(notebook, function, source)
    assert message, f"the public tests of {function} pass with the mistake"
    for word in words:
        assert word in message, f"the hint does not say {word!r}: {message}"


ENTRIES = sorted(p.stem for p in BUGGY.glob("*.py"))


def test_every_buggy_entry_has_the_words_its_hint_must_say():
    assert set(HINTS) == set(ENTRIES), (
        f"buggy entries without HINTS: {sorted(set(ENTRIES) - set(HINTS))}; HINTS of no entry: {sorted(set(HINTS) - set(ENTRIES))}"
    )


@pytest.mark.slow
@pytest.mark.parametrize("entry", ENTRIES)
def test_every_buggy_entry_fails_a_public_test_whose_message_names_its_mistake(entry):
    bug = load_entry(BUGGY / f"{entry}.py")
    messages = public_failures(bug.notebook, bug.solutions, set(bug.solutions) | set(bug.loses))
    failed = {f: m for f, m in messages.items() if m}
    assert failed, f"{entry} passes every public test of {sorted(messages)}: the hidden tests catch what no public test names"
    assert hinted(entry, messages), f"{entry}: no failing public test says {HINTS[entry]}: {failed}"
