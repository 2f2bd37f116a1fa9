"""The stage 02 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import reference.shape_matching as stage01
import reference.sign_correction as ref
from grader.checks import check_namespace, all_checks
from deformlab_packs.deformation.checks.sign_correction import det_verdict, rotation_verdicts
from deformlab_packs.deformation.checks.generators import random_rotation


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def failed(result):
    return result.failed_verdicts()


def rotation_without_sign_correction(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, float))
    return np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)


def rotation_flipping_the_largest_singular_value(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, float))
    V, Ut = np.swapaxes(Vt, -1, -2), np.swapaxes(U, -1, -2)
    D = np.ones(np.shape(S)[:-1])
    D[..., 0] = np.sign(np.linalg.det(V @ Ut))
    return V @ (D[..., :, None] * Ut)


def rotation_transposed(S):
    return np.swapaxes(ref.optimal_rotation(S), -1, -2)


def rigid_align_without_sign_correction(P, Q, w=None):
    return stage01.orthogonal_align(P, Q, w)


def rigid_align_transposed(P, Q, w=None):
    R, _ = ref.rigid_align(P, Q, w)
    return R.T, stage01.centroid(Q, w) - R.T @ stage01.centroid(P, w)


@pytest.mark.parametrize(
    "function, implementation, verdict",
    [
        ("optimal_rotation", rotation_without_sign_correction, "det = +1"),
        ("optimal_rotation", rotation_flipping_the_largest_singular_value, "optimal tr(R S) over rotations"),
        ("optimal_rotation", rotation_transposed, "optimal tr(R S) over rotations"),
        ("optimal_rotation", lambda S: ref.optimal_rotation(S)[..., :1, :, :] if np.ndim(S) == 3 else ref.optimal_rotation(S), "output shape"),
        ("rigid_align", rigid_align_without_sign_correction, "det = +1"),
        ("rigid_align", rigid_align_transposed, "optimal Σ w‖R p + t − q‖²"),
    ],
    ids=[
        "rotation: no sign correction",
        "rotation: sign on the largest singular value",
        "rotation: transposed",
        "rotation: a stack collapsed to its first matrix",
        "align: no sign correction",
        "align: transposed R",
    ],
)
def test_realistic_mistakes_fail(function, implementation, verdict):
    assert verdict in failed(grade(function, implementation))


def test_any_maximizer_passes_for_rank_deficient_matrices():
    def another_maximizer(S):
        """The reference's R, turned about u for a rank-1 ``S = σ u vᵀ`` (tr(R S) = σ vᵀ R u is unchanged), any rotation for ``S = 0``."""
        R = np.array(ref.optimal_rotation(S))
        flat, stack = R.reshape(-1, *R.shape[-2:]), np.reshape(S, (-1, *R.shape[-2:]))
        for k, Sk in enumerate(stack):
            if not np.any(Sk):
                flat[k] = random_rotation(np.random.default_rng(k), len(Sk))
            elif len(Sk) == 3 and np.linalg.matrix_rank(Sk) == 1:
                u = np.linalg.svd(Sk)[0][:, 0]
                K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
                flat[k] = flat[k] @ (np.eye(3) + np.sin(1.0) * K + (1.0 - np.cos(1.0)) * K @ K)
        return flat.reshape(R.shape)

    cases = all_checks()["optimal_rotation"].cases(np.random.default_rng(0))
    assert any(not np.allclose(another_maximizer(c.args()[0]), ref.optimal_rotation(c.args()[0])) for c in cases)
    assert grade("optimal_rotation", another_maximizer).fraction == 1.0


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), d=st.sampled_from([2, 3]))
def test_rotation_verdicts_accept_rotations_and_reject_reflections(seed, d):
    rng = np.random.default_rng(seed)
    R = random_rotation(rng, d)
    assert all(v.passed for v in rotation_verdicts(R))
    mirror = R @ np.diag([-1.0] + [1.0] * (d - 1))
    assert not det_verdict(mirror).passed
    assert "reflection" in det_verdict(mirror).detail
