"""A common mistake makes the public tests fail with a message that names it."""

from pathlib import Path

import pytest

from grader.build.authored import read_authored
from grader.pipeline.sanitize import _calls_contract_at_top_level

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks" / "deformation"

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
    namespace: dict = {}
    for cell in read_authored(NOTEBOOKS / f"{notebook}.py").cells:
        if cell.kind == "provided" and not _calls_contract_at_top_level(cell.source):
            exec(compile(cell.source, notebook, "exec"), namespace)
        elif cell.kind == "solution":
            exec(compile(source if cell.function == function else cell.source, notebook, "exec"), namespace)
        elif cell.kind == "tests" and cell.function == function:
            try:
                exec(compile(cell.source, notebook, "exec"), namespace)
            except AssertionError as exc:
                return str(exc)
            return ""
    raise AssertionError(f"{notebook} has no tests cell for {function}")


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
