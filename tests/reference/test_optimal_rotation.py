import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st
from scipy.stats import ortho_group, special_ortho_group

from reference.shape_matching import covariance_matrix, optimal_orthogonal
from reference.sign_correction import optimal_rotation
from starter.meshes import load_mesh

dims = st.sampled_from([2, 3])
seeds = st.integers(0, 2**32 - 1)
KINDS = [
    "gaussian", "near rotation", "near reflection", "rank d-1", "rank 1", "zero",
    "mirrored, equal small singular values", "ill-conditioned", "huge", "tiny", "small integers",
]


def random_stack(kind, d, k, rng):
    """``k`` matrices ``(d, d)`` of one family, including the degenerate ones."""
    Q = special_ortho_group.rvs(d, size=k, random_state=rng).reshape(k, d, d)
    Q2 = ortho_group.rvs(d, size=k, random_state=rng).reshape(k, d, d)
    mirror = np.diag([1.0] * (d - 1) + [-1.0])
    if kind == "gaussian":
        return rng.normal(size=(k, d, d))
    if kind == "near rotation":
        return Q + 10.0 ** rng.uniform(-15, -2, size=(k, 1, 1)) * rng.normal(size=(k, d, d))
    if kind == "near reflection":
        return Q @ mirror + 10.0 ** rng.uniform(-15, -2, size=(k, 1, 1)) * rng.normal(size=(k, d, d))
    if kind == "rank d-1":
        P = rng.normal(size=(k, d, d))
        P[:, :, -1] = 0.0
        return Q @ P @ Q2
    if kind == "rank 1":
        return rng.normal(size=(k, d, 1)) * rng.normal(size=(k, 1, d))
    if kind == "zero":
        return np.zeros((k, d, d))
    if kind == "mirrored, equal small singular values":
        sv = rng.uniform(0.1, 1.0, size=(k, d))
        sv[:, 0] = 1.0
        sv[:, -1] = sv[:, -2] * (1.0 + rng.choice([0.0, 1e-12, 1e-8, 1e-4], size=k))
        return Q @ (sv[:, :, None] * mirror) @ Q2
    if kind == "ill-conditioned":
        sv = rng.uniform(0.0, 1.0, size=(k, d)) ** rng.choice([1, 5, 20], size=(k, d))
        signs = rng.choice([-1.0, 1.0], size=(k, d))
        return Q @ (sv[:, :, None] * np.eye(d) * signs[:, None, :]) @ Q2
    if kind == "huge":
        return 1e250 * rng.normal(size=(k, d, d))
    if kind == "tiny":
        return 1e-250 * rng.normal(size=(k, d, d))
    return rng.integers(-2, 3, size=(k, d, d)).astype(np.float64)


def best_rotation_trace(S):
    """``max tr(R S)`` over rotations by the SVD: ``σ₁ + ... + σ_{d-1} ± σ_d``."""
    U, sv, Vt = np.linalg.svd(S)
    sign = np.sign(np.linalg.det(U @ Vt))
    return sv[..., :-1].sum(axis=-1) + sign * sv[..., -1]


def assert_optimal_rotations(R, S):
    assert R.shape == S.shape and R.dtype == np.float64
    d = S.shape[-1]
    RtR = np.swapaxes(R, -1, -2) @ R
    np.testing.assert_allclose(RtR, np.broadcast_to(np.eye(d), RtR.shape), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, rtol=0, atol=1e-12)
    # compare on S / max|S_ij| so that huge and tiny stacks are judged alike
    scale = np.abs(S).max(axis=(-2, -1))
    scale = np.where(scale > 0, scale, 1.0)
    S_unit = S / scale[..., None, None]
    achieved = np.einsum("...ij,...ji->...", R, S_unit)
    np.testing.assert_allclose(achieved, best_rotation_trace(S_unit), rtol=0, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(KINDS), dims, seeds)
def test_stacks_of_random_and_degenerate_matrices_get_optimal_rotations(kind, d, seed):
    # 60 examples x 30 000 matrices: about two million matrices checked against the SVD
    S = random_stack(kind, d, 30_000, np.random.default_rng(seed))
    assert_optimal_rotations(optimal_rotation(S), S)


@settings(max_examples=100, deadline=None)
@given(dims, seeds)
def test_no_rotation_gives_a_larger_trace(d, seed):
    rng = np.random.default_rng(seed)
    S = rng.normal(size=(d, d))
    best = np.trace(optimal_rotation(S) @ S)
    others = special_ortho_group.rvs(d, size=200, random_state=rng)
    assert (np.einsum("kij,ji->k", others, S) <= best + 1e-12 * np.abs(S).sum()).all()


def point_sets(d, kind, rng, k=12):
    """Points spanning ``d - 1`` dimensions (planar), one (collinear) or none (coincident)."""
    if kind == "planar":
        P = np.c_[rng.normal(size=(k, d - 1)), np.zeros(k)]
    elif kind == "collinear":
        P = np.outer(rng.normal(size=k), rng.normal(size=d))
    else:
        P = np.tile(rng.normal(size=d), (k, 1))
    return P @ ortho_group.rvs(d, random_state=rng).T + rng.normal(size=d)


@settings(max_examples=100, deadline=None)
@given(dims, st.sampled_from(["planar", "collinear", "coincident"]), seeds)
def test_rank_deficient_and_mirrored_point_sets_give_optimal_rotations(d, kind, seed):
    rng = np.random.default_rng(seed)
    P = point_sets(d, kind, rng)
    mirrored = P @ np.diag([1.0] * (d - 1) + [-1.0]) @ special_ortho_group.rvs(d, random_state=rng).T
    others = (rng.normal(size=P.shape), mirrored, P)
    S = np.stack([covariance_matrix(A, B) for Q in others for A, B in ((P, Q), (Q, P))])
    assert_optimal_rotations(optimal_rotation(S), S)


@settings(max_examples=50, deadline=None)
@given(dims, seeds)
def test_a_mirrored_point_set_flips_the_direction_of_the_smallest_singular_value(d, seed):
    rng = np.random.default_rng(seed)
    # distinct spreads along the axes, then mirrored across the last one and rotated
    P = rng.normal(size=(40, d)) * np.arange(d, 0, -1)
    P -= P.mean(axis=0)
    Q0 = special_ortho_group.rvs(d, random_state=rng)
    S = covariance_matrix(P, P @ np.diag([1.0] * (d - 1) + [-1.0]) @ Q0.T)
    U, _, Vt = np.linalg.svd(S)
    flip = np.diag([1.0] * (d - 1) + [-1.0])
    np.testing.assert_allclose(optimal_rotation(S), Vt.T @ flip @ U.T, atol=1e-9)


def test_known_answers():
    # det S < 0: the identity gives 3 + 2 - 1, the best a rotation can do
    np.testing.assert_allclose(optimal_rotation(np.diag([3.0, 2.0, -1.0])), np.eye(3), atol=1e-15)
    # det S > 0: a half turn about z makes every diagonal entry positive
    np.testing.assert_allclose(optimal_rotation(np.diag([-1.0, -2.0, 3.0])), np.diag([-1.0, -1.0, 1.0]), atol=1e-15)

    def rot2(a):
        return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])

    np.testing.assert_allclose(optimal_rotation(rot2(0.7) @ np.diag([3.0, 1.0])), rot2(-0.7), atol=1e-15)
    np.testing.assert_allclose(optimal_rotation(np.diag([1.0, -1.0])), np.eye(2), atol=1e-15)


@settings(max_examples=50, deadline=None)
@given(dims, seeds)
def test_a_rotation_gives_its_transpose_and_matches_optimal_orthogonal_when_det_is_positive(d, seed):
    rng = np.random.default_rng(seed)
    Q = special_ortho_group.rvs(d, size=20, random_state=rng)
    np.testing.assert_allclose(optimal_rotation(Q), np.swapaxes(Q, 1, 2), atol=1e-12)
    S = rng.normal(size=(d, d))
    S[0] *= np.sign(np.linalg.det(S))
    if d == 2 or np.linalg.svd(S, compute_uv=False)[-1] > 1e-3:
        np.testing.assert_allclose(optimal_rotation(S), optimal_orthogonal(S), atol=1e-9)


def test_a_single_matrix_gives_the_same_rotation_as_in_a_stack():
    rng = np.random.default_rng(3)
    for d in (2, 3):
        S = rng.normal(size=(7, d, d))
        R = optimal_rotation(S)
        for i in range(7):
            single = optimal_rotation(S[i])
            assert single.shape == (d, d)
            np.testing.assert_allclose(single, R[i], atol=1e-15)


def test_local_steps_of_a_deformed_real_mesh():
    V, F = load_mesh("bar")
    rng = np.random.default_rng(4)
    U = V @ special_ortho_group.rvs(3, random_state=rng).T + 0.05 * rng.normal(size=V.shape)
    # one-ring covariances: most are rank 2 because the bar's sides are flat
    S = np.zeros((len(V), 3, 3))
    for corner in range(3):
        a, b = F[:, (corner + 1) % 3], F[:, (corner + 2) % 3]
        T = np.einsum("ta,tb->tab", V[a] - V[b], U[a] - U[b])
        for i in range(3):
            np.add.at(S, F[:, i], T)
    flat = np.linalg.svd(S, compute_uv=False)
    assert (flat[:, 2] < 1e-12 * flat[:, 0]).mean() > 0.5
    assert_optimal_rotations(optimal_rotation(S), S)


def test_empty_stacks_give_empty_stacks():
    for d in (2, 3):
        assert optimal_rotation(np.zeros((0, d, d))).shape == (0, d, d)


def test_input_is_not_modified():
    S = np.random.default_rng(0).normal(size=(5, 3, 3))
    S0 = S.copy()
    optimal_rotation(S)
    np.testing.assert_array_equal(S, S0)


@pytest.mark.parametrize(
    "S, message",
    [
        (np.ones(3), r"S must be a \(d, d\) matrix or a \(k, d, d\) stack"),
        (np.ones((2, 3)), r"S must be a \(d, d\) matrix or a \(k, d, d\) stack"),
        (np.ones((4, 4)), r"S must be a \(d, d\) matrix or a \(k, d, d\) stack"),
        (np.ones((5, 3, 2)), r"S must be a \(d, d\) matrix or a \(k, d, d\) stack"),
        (np.ones((2, 2, 3, 3)), r"S must be a \(d, d\) matrix or a \(k, d, d\) stack"),
        (np.array([[[1.0, np.nan], [0.0, 1.0]]]), "S contains NaN or inf"),
        (np.array([[np.inf, 0, 0], [0, 1, 0], [0, 0, 1]]), "S contains NaN or inf"),
        (np.array([["a", "b"], ["c", "d"]]), "S must be a numeric array"),
        (sp.eye(3, format="csr"), "S must be a dense array"),
    ],
)
def test_bad_inputs_raise_value_error_naming_s(S, message):
    with pytest.raises(ValueError, match=message):
        optimal_rotation(S)
