"""The stage 05 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import scipy.sparse as sp

from grader.checks import check_namespace, all_checks, evaluate, reference_outputs, wire
from grader.harness.outputs import CaseOutput

# The package re-exports the function lbs(), which hides the module attribute ``reference.linear_blend_skinning``.
ref = importlib.import_module("reference.linear_blend_skinning")


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def failed(result):
    return result.failed_verdicts()


def test_a_sparse_lbs_matrix_is_accepted():
    assert grade("lbs_matrix", lambda V, W: sp.csc_matrix(ref.lbs_matrix(V, W))).fraction == 1.0


def lbs_matrix_coordinate_major(V, W):
    n, m = W.shape
    return ref.lbs_matrix(V, W).reshape(n, m, -1).transpose(0, 2, 1).reshape(n, -1)


def lbs_matrix_without_homogeneous_one(V, W):
    M = ref.lbs_matrix(V, W).reshape(len(V), W.shape[1], -1)
    M[:, :, -1] = 0.0
    return M.reshape(len(V), -1)


def lbs_without_translation(V, W, T):
    return np.einsum("ij,jab,ib->ia", W, T[:, :, :-1], V)


def lbs_with_transposed_linear_part(V, W, T):
    return np.einsum("ij,jba,ib->ia", W, T[:, :, :-1], V) + W @ T[:, :, -1]


def lbs_with_normalized_weights(V, W, T):
    return ref.lbs(V, W / W.sum(axis=1, keepdims=True), T)


@pytest.mark.parametrize(
    "function, implementation, verdict",
    [
        ("lbs_matrix", lbs_matrix_coordinate_major, "M matches the layout M[i, j(d+1)+c] = W[i, j]·[v_i; 1][c]"),
        ("lbs_matrix", lbs_matrix_without_homogeneous_one, "M matches the layout M[i, j(d+1)+c] = W[i, j]·[v_i; 1][c]"),
        ("lbs", lbs_without_translation, "one rigid transform for every handle moves the mesh rigidly"),
        ("lbs", lbs_with_transposed_linear_part, "one rigid transform for every handle moves the mesh rigidly"),
        ("lbs", lbs_with_normalized_weights, "U = Σ_j W[i, j] T_j [v_i; 1]"),
    ],
    ids=["matrix: coordinate-major columns", "matrix: no homogeneous 1", "lbs: translation dropped", "lbs: Aᵀ", "lbs: weights renormalized"],
)
def test_realistic_mistakes_fail(function, implementation, verdict):
    assert verdict in failed(grade(function, implementation))


def test_identity_transforms_are_checked_against_the_rest_positions():
    def shifted(V, W, T):
        return ref.lbs(V, W, T) + 1e-6

    assert "identity transforms return V" in failed(grade("lbs", shifted))


def test_column_order_feedback_names_the_layout():
    assert "coordinate-major" in grade("lbs_matrix", lbs_matrix_coordinate_major).summary()


def test_nan_in_an_otherwise_correct_output_fails_cleanly():
    checks = all_checks()["lbs"]
    cases = checks.cases(np.random.default_rng(0))
    expected = reference_outputs(cases)
    outputs = []
    for e in expected:
        U = wire(e).copy()
        U[-1, 0] = np.nan
        outputs.append(CaseOutput(U, None, None))
    result = evaluate(checks, cases, outputs, expected)
    assert result.fraction == 0.0 and failed(result) == {"output shape"}
