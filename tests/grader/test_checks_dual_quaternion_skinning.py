"""The dual-quaternion skinning checks fail realistic mistakes, with hints, and accept correct variations."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from grader.checks import check_namespace

# The package re-exports dqs(), which hides the module attribute ``reference.dual_quaternion_skinning``.
ref = importlib.import_module("reference.dual_quaternion_skinning")


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def details(result):
    return " ".join(v.detail for c in result.cases for v in c.verdicts if not v.passed)


def dual_quaternions_scalar_last(T):
    return ref.dual_quaternions(T)[:, :, [1, 2, 3, 0]]


def dual_quaternions_of_the_inverse_rotation(T):
    Q = ref.dual_quaternions(np.concatenate([T[:, :, :3].transpose(0, 2, 1), T[:, :, 3:]], axis=2))
    return np.stack([Q[:, 0], ref.dual_quaternions(T)[:, 1]], axis=1)


def dual_quaternions_product_reversed(T):
    Q = ref.dual_quaternions(T)
    w, v, t = Q[:, 0, 0], Q[:, 0, 1:], T[:, :, 3]
    Q[:, 1] = 0.5 * np.c_[-np.einsum("ji,ji->j", v, t), w[:, None] * t + np.cross(v, t)]  # ½ q_0 (0, t)
    return Q


def dual_quaternion_transforms_transposed(Q):
    T = ref.dual_quaternion_transforms(Q)
    T[:, :, :3] = T[:, :, :3].transpose(0, 2, 1)
    return T


def dual_quaternion_transforms_unnormalized(Q):
    Q = np.asarray(Q, float).copy()
    Q[:, 1] *= np.linalg.norm(Q[:, 0], axis=1)[:, None]  # only q_0 is normalized
    return ref.dual_quaternion_transforms(Q)


def dqs_blending_matrices(V, W, T):
    return np.einsum("ij,jab,ib->ia", W, T[:, :, :3], V) + W @ T[:, :, 3]


def dqs_without_sign_choice(V, W, T):
    Q = ref.dual_quaternions(T)
    blended = ref.dual_quaternion_transforms((W @ Q.reshape(len(Q), 8)).reshape(len(V), 2, 4))
    return np.einsum("iab,ib->ia", blended[:, :, :3], V) + blended[:, :, 3]


@pytest.mark.parametrize(
    "function, implementation, hint",
    [
        ("dual_quaternions", dual_quaternions_scalar_last, "scalar first"),
        ("dual_quaternions", dual_quaternions_of_the_inverse_rotation, "quaternion of Rᵀ"),
        ("dual_quaternions", dual_quaternions_product_reversed, "quaternion products do not commute"),
        ("dual_quaternion_transforms", dual_quaternion_transforms_transposed, "R is transposed"),
        ("dual_quaternion_transforms", dual_quaternion_transforms_unnormalized, "divided by ‖q_0‖"),
        ("dqs", dqs_blending_matrices, "this is linear blend skinning"),
        ("dqs", dqs_without_sign_choice, "flip every handle"),
    ],
)
def test_a_common_mistake_fails_with_its_hint(function, implementation, hint):
    result = grade(function, implementation)
    assert result.fraction < 1.0
    assert hint in details(result)


def test_dual_quaternions_of_either_sign_per_handle_are_accepted():
    def alternating_signs(T):
        Q = ref.dual_quaternions(T)
        Q[::2] *= -1.0
        return Q

    assert grade("dual_quaternions", alternating_signs).fraction == 1.0


def _via_scipy(T):
    q = Rotation.from_matrix(T[:, :, :3]).as_quat()[:, [3, 0, 1, 2]]
    t = np.c_[np.zeros(len(T)), T[:, :, 3]]
    w1, v1, w2, v2 = t[:, 0], t[:, 1:], q[:, 0], q[:, 1:]
    qe = 0.5 * np.c_[w1 * w2 - np.einsum("ij,ij->i", v1, v2), w1[:, None] * v2 + w2[:, None] * v1 + np.cross(v1, v2)]
    return np.stack([q, qe], axis=1)


def test_dual_quaternions_through_scipy_are_accepted():
    def via_scipy(T):
        R = T[:, :, :3]
        bad = (np.abs(np.einsum("jki,jkl->jil", R, R) - np.eye(3)).max(axis=(1, 2)) > 1e-6) | (np.linalg.det(R) < 0)
        if bad.any():
            raise ValueError(f"T[{int(np.argmax(bad))}] is not rigid")
        return _via_scipy(T)

    assert grade("dual_quaternions", via_scipy).fraction == 1.0


def test_dual_quaternions_without_the_contracts_check_lose_exactly_the_cases_that_must_raise():
    # scipy's from_matrix orthogonalizes a scaled matrix quietly (and refuses a reflection on its own)
    result = grade("dual_quaternions", _via_scipy)
    failed = [c.label for c in result.cases if not c.passed]
    assert failed == ["T[1]'s 3x3 part is a rotation scaled by 1.5 (not rigid)"], failed
    assert "returned a result instead of raising ValueError" in details(result)


def test_dqs_with_a_loop_over_vertices_and_the_pivot_flipped_per_vertex_is_accepted():
    def loop(V, W, T):
        Q = ref.dual_quaternions(T)
        U = np.empty_like(V)
        for i, (v, w) in enumerate(zip(V, W)):
            b = sum(w_j * (q if q[0] @ Q[0, 0] >= 0 else -q) for w_j, q in zip(w, Q))
            Ti = ref.dual_quaternion_transforms(b[None])[0]
            U[i] = Ti[:, :3] @ v + Ti[:, 3]
        return U

    assert grade("dqs", loop).fraction == 1.0
