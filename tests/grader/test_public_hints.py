"""A common mistake makes the public tests fail with a message that names it."""

import pytest

from tests.corpus import load_entry
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


SINGLE_MATRIX_ROTATION = '''
import numpy as np


def optimal_rotation(S):
    U_svd, sigma, U_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    D = np.eye(len(sigma))
    D[-1, -1] = np.sign(np.linalg.det(U_tilde_T.T @ U_svd.T))  # one matrix only: a stack breaks here
    return U_tilde_T.T @ D @ U_svd.T
'''

WEIGHT_ON_AN_EDGE_THROUGH_ITS_CORNER = '''
import numpy as np
import scipy.sparse as sp


def cotangent_laplacian(V, F):
    F = np.asarray(F, dtype=np.int64)
    n = len(V)
    C = cotangent_weights(V, F)
    i = np.concatenate([F[:, k] for k in range(3)])  # corner k's weight on the edge (k, k+1): not opposite k
    j = np.concatenate([F[:, (k + 1) % 3] for k in range(3)])
    off = sp.coo_matrix((C.T.ravel(), (i, j)), shape=(n, n))
    off = (off + off.T).tocsr()
    return off - sp.diags(np.asarray(off.sum(axis=1)).ravel())
'''

WEIGHT_OF_THE_NEXT_CORNER = '''
import numpy as np


def cotangent_weights(V, F):
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    C = np.empty(F.shape)
    for k in range(3):
        a = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        b = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        sin = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) if V.shape[1] == 2 else np.linalg.norm(np.cross(a, b), axis=1)
        C[:, (k + 1) % 3] = 0.5 * np.sum(a * b, axis=1) / sin  # stored in the next corner's column
    return C
'''

GLOBAL_STEP_WITHOUT_HANDLE_COLUMNS = '''
import numpy as np


def arap_global_step(data, R, handle_positions):
    V, a, b = data.V, data.a, data.b
    R_mean = np.asarray(R, dtype=float)[data.F].mean(axis=1)
    pull = data.C.ravel()[:, None] * np.einsum("tij,tj->ti", np.repeat(R_mean, 3, axis=0), V[a] - V[b])
    B = data.D @ pull
    U = np.empty_like(V)
    U[data.handles] = handle_positions
    U[data.free] = data.K_ff.solve(B[data.free])  # the handles' columns are never moved to the right
    return U
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
        ("02_sign_correction", "optimal_rotation", SINGLE_MATRIX_ROTATION, ("stack", "np.swapaxes", "[..., -1]")),
        ("03_arap", "optimal_rotation", SINGLE_MATRIX_ROTATION, ("stack", "np.swapaxes", "[..., -1]")),
        ("03_arap", "cotangent_laplacian", WEIGHT_ON_AN_EDGE_THROUGH_ITS_CORNER, ("OPPOSITE corner k",)),
        ("03_arap", "cotangent_weights", WEIGHT_OF_THE_NEXT_CORNER, ("wrong columns", "AT corner k")),
        ("03b_arap_global", "arap_global_step", GLOBAL_STEP_WITHOUT_HANDLE_COLUMNS, ("handle columns are missing",)),
    ],
    ids=["02 transposed rotation", "01 transposed orthogonal map", "02 flipped the largest singular value",
         "02 one matrix only", "03 one matrix only", "03 weight on an edge through its corner",
         "03 weight in the next corner's column",
         "03b global step without the handle columns"],
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
