"""The stage 01 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import reference.shape_matching as ref
from grader.checks import check_namespace, all_checks, evaluate, reference_outputs, wire
from deformlab_packs.deformation.checks.generators import random_rotation
from deformlab_packs.deformation.checks.shape_matching import orthonormal_verdict, trace_verdict
from grader.harness.outputs import CaseOutput


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def failed(result):
    return result.failed_verdicts()


def _weights(P, w):
    return np.ones(len(P)) if w is None else np.asarray(w, float)


def covariance_uncentred(P, Q, w=None):
    return P.T @ (_weights(P, w)[:, None] * Q)


def covariance_unweighted_centroids(P, Q, w=None):
    return (P - P.mean(0)).T @ (_weights(P, w)[:, None] * (Q - Q.mean(0)))


def orthogonal_transposed(S):
    U, _, Vt = np.linalg.svd(S)
    return U @ Vt


def align_without_rotating_the_centroid(P, Q, w=None):
    R = ref.optimal_orthogonal(ref.covariance_matrix(P, Q, w))
    return R, ref.centroid(Q, w) - ref.centroid(P, w)


def align_with_transposed_rotation(P, Q, w=None):
    R, _ = ref.orthogonal_align(P, Q, w)
    return R.T, ref.centroid(Q, w) - R.T @ ref.centroid(P, w)


@pytest.mark.parametrize(
    "function, implementation, verdict",
    [
        ("centroid", lambda P, w=None: P.mean(axis=0), "weighted mean"),
        ("centroid", lambda P, w=None: _weights(P, w) @ P / len(P), "weighted mean"),
        ("covariance_matrix", covariance_uncentred, "S matches"),
        ("covariance_matrix", covariance_unweighted_centroids, "S matches"),
        ("covariance_matrix", lambda P, Q, w=None: ref.covariance_matrix(P, Q, w).T, "S matches"),
        ("optimal_orthogonal", orthogonal_transposed, "optimal tr(R S) over orthogonal R"),
        ("optimal_orthogonal", lambda S: S / np.linalg.norm(S, 2) if np.any(S) else np.eye(len(S)), "orthonormal"),
        ("orthogonal_align", align_without_rotating_the_centroid, "optimal Σ w‖R p + t − q‖²"),
        ("orthogonal_align", align_with_transposed_rotation, "optimal Σ w‖R p + t − q‖²"),
    ],
    ids=[
        "centroid: weights ignored",
        "centroid: divided by k instead of Σw",
        "covariance: points not centred",
        "covariance: unweighted centroids",
        "covariance: transposed",
        "orthogonal: U Vᵀ instead of V Uᵀ",
        "orthogonal: S scaled, not orthogonalized",
        "align: t = q̄ − p̄",
        "align: transposed R",
    ],
)
def test_realistic_mistakes_fail(function, implementation, verdict):
    assert verdict in failed(grade(function, implementation))


def test_covariance_feedback_names_the_mistake():
    summary = grade("covariance_matrix", covariance_uncentred).summary()
    assert "not centred" in summary


def test_a_reflection_is_accepted_where_it_is_optimal():
    # Stage 01 allows det = -1: the reference's reflections pass, and so does any other maximizer.
    def other_maximizer(S):
        R = ref.optimal_orthogonal(S)
        # For the zero matrix every orthogonal matrix is optimal.
        return -np.eye(len(S)) if not np.any(S) else R

    assert grade("optimal_orthogonal", other_maximizer).fraction == 1.0


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([2, 3]), k=st.integers(1, 6))
def test_orthonormal_and_trace_verdicts_accept_exact_maximizers(seed, d, k):
    rng = np.random.default_rng(seed)
    S = rng.normal(size=(k, d, d))
    U, sigma, Vt = np.linalg.svd(S)
    R = np.swapaxes(Vt, 1, 2) @ np.swapaxes(U, 1, 2)
    assert orthonormal_verdict(R).passed
    assert trace_verdict(R, S, sigma.sum(axis=1), "optimal").passed
    # Any other orthogonal matrix falls short of Σσ on a generic S.
    Q = np.stack([random_rotation(rng, d) for _ in range(k)]) @ R
    assert not trace_verdict(Q, S, sigma.sum(axis=1), "optimal").passed


def test_nan_in_a_pair_fails_cleanly():
    checks = all_checks()["orthogonal_align"]
    cases = checks.cases(np.random.default_rng(0))
    expected = reference_outputs(cases)
    outputs = [CaseOutput((np.full_like(R, np.nan), t), None, None) for R, t in (wire(e) for e in expected)]
    result = evaluate(checks, cases, outputs, expected)
    assert result.fraction == 0.0 and failed(result) == {"output shape"}


def test_the_scaled_and_moved_copy_has_the_original_answer_up_to_the_same_similarity():
    from deformlab_packs.deformation.checks.shape_matching import alignment_objective, alignment_point_sets

    sets = {label: (P, Q, w) for label, P, Q, w in alignment_point_sets(np.random.default_rng(12))}
    original = sets["2D weighted, noisy rotated copy"]
    copy = sets["the 2D weighted problem again, scaled by 1/100, turned and moved 50 units away"]
    assert np.linalg.norm(copy[0].mean(axis=0)) > 45.0
    best, best_copy = (alignment_objective(*ref.orthogonal_align(P, Q, w), P, Q, w) for P, Q, w in (original, copy))
    assert np.isclose(best_copy, 1e-4 * best, rtol=1e-6)
