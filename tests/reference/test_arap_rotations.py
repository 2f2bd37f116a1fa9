import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import ortho_group, special_ortho_group

from reference.arap import (
    arap_covariances, arap_energy, arap_rotations, cell_rotations_transposed, cotangent_weights,
)
from reference.sign_correction import optimal_rotation
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "bar", "character"])


def deformed(V, rng, noise):
    d = V.shape[1]
    return V @ special_ortho_group.rvs(d, random_state=rng).T + noise * rng.normal(size=V.shape)


@settings(max_examples=20, deadline=None)
@given(meshes, st.sampled_from([0.0, 0.01, 0.1, 1.0]), seeds)
def test_every_rotation_maximizes_the_trace_with_its_covariance(mesh, noise, seed):
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    U = deformed(V, rng, noise)
    C = cotangent_weights(V, F)
    R = arap_rotations(V, U, F, C)
    S = arap_covariances(V, U, F, C)
    assert R.shape == (len(V), d, d)
    np.testing.assert_allclose(np.swapaxes(R, 1, 2) @ R, np.broadcast_to(np.eye(d), R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    Us, sv, Vt = np.linalg.svd(S)
    best = sv[:, :-1].sum(axis=1) + np.sign(np.linalg.det(Us @ Vt)) * sv[:, -1]
    np.testing.assert_allclose(np.einsum("kij,kji->k", R, S), best, rtol=0, atol=1e-12 * sv[:, 0].max())


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_a_rigid_motion_is_recovered_at_every_vertex(mesh, seed):
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    Q = special_ortho_group.rvs(d, random_state=rng)
    R = arap_rotations(V, V @ Q.T + rng.normal(size=d), F, cotangent_weights(V, F))
    np.testing.assert_allclose(R, np.broadcast_to(Q, R.shape), atol=1e-9)


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_the_local_step_never_raises_the_energy(mesh, seed):
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    U = deformed(V, rng, 0.05)
    C = cotangent_weights(V, F)
    R = arap_rotations(V, U, F, C)
    best = arap_energy(V, U, F, C, R)
    # any other rotations, near or far, do worse
    for other in (
        special_ortho_group.rvs(d, size=len(V), random_state=rng),
        arap_rotations(V, U + 0.01 * rng.normal(size=U.shape), F, C),
    ):
        assert arap_energy(V, U, F, C, other) >= best - 1e-12 * best


def test_bad_inputs_raise_value_error_naming_the_argument():
    V, F = load_mesh("bar_coarse")
    C = cotangent_weights(V, F)
    with pytest.raises(ValueError, match="U must have the shape of V"):
        arap_rotations(V, V[:, :2], F, C)
    with pytest.raises(ValueError, match=r"C must have shape \(900, 3\)"):
        arap_rotations(V, V, F, C.T)


MIRROR = np.diag([1.0, 1.0, -1.0])
STACKS = [
    "gaussian", "near rotation", "near reflection", "flat (rank 2)", "mirrored flat", "rank 1", "zero",
    "mirrored, equal small singular values", "ill-conditioned", "huge", "tiny",
]


def stack(kind, k, rng):
    """``k`` 3x3 matrices of one family, the ill-determined ones included."""
    Q = special_ortho_group.rvs(3, size=k, random_state=rng)
    Q2 = ortho_group.rvs(3, size=k, random_state=rng)
    if kind == "gaussian":
        return rng.normal(size=(k, 3, 3))
    if kind == "near rotation":
        return Q + 10.0 ** rng.uniform(-15, -1, size=(k, 1, 1)) * rng.normal(size=(k, 3, 3))
    if kind == "near reflection":
        return Q @ MIRROR + 10.0 ** rng.uniform(-15, -1, size=(k, 1, 1)) * rng.normal(size=(k, 3, 3))
    if kind in ("flat (rank 2)", "mirrored flat"):
        # a flat one-ring's covariance: rest edges in a plane
        P = rng.normal(size=(k, 3, 3))
        P[:, :, 2] = 0.0
        return Q @ P @ (Q2 @ MIRROR if kind == "mirrored flat" else Q2)
    if kind == "rank 1":
        return rng.normal(size=(k, 3, 1)) * rng.normal(size=(k, 1, 3))
    if kind == "zero":
        return np.zeros((k, 3, 3))
    if kind == "mirrored, equal small singular values":
        sv = rng.uniform(0.1, 1.0, size=(k, 3))
        sv[:, 0] = 1.0
        sv[:, 2] = sv[:, 1] * (1.0 + rng.choice([0.0, 1e-12, 1e-8, 1e-4, 1e-2], size=k))
        return Q @ (sv[:, :, None] * MIRROR) @ Q2
    if kind == "ill-conditioned":
        sv = rng.uniform(0.0, 1.0, size=(k, 3)) ** rng.choice([1, 5, 20], size=(k, 3))
        return Q @ (sv[:, :, None] * np.eye(3) * rng.choice([-1.0, 1.0], size=(k, 1, 3))) @ Q2
    return (1e250 if kind == "huge" else 1e-250) * rng.normal(size=(k, 3, 3))


def svd_rotations(S):
    """The lecture's ``R = Ũ D Uᵀ`` for ``S = U Σ Ũᵀ``, ``D = diag(1, 1, det(Ũ Uᵀ))``, and how well it is determined.

    The rotation is determined up to ``~ε / g`` for ``g = (σ₂ + s σ₃) / σ₁``,
    ``s = det(Ũ Uᵀ)``: the smallest sum of two signed singular values.
    """
    U, sv, Vt = np.linalg.svd(S)
    sign = np.sign(np.linalg.det(U @ Vt))
    D = np.ones((len(S), 3))
    D[:, 2] = sign
    R = np.swapaxes(Vt, 1, 2) @ (D[:, :, None] * np.swapaxes(U, 1, 2))
    gap = (sv[:, 1] + sign * sv[:, 2]) / np.where(sv[:, 0] > 0, sv[:, 0], 1.0)
    return R, gap


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(STACKS), seeds)
def test_the_polar_formula_gives_the_sign_corrected_svd_rotation_to_1e_12(kind, seed):
    # 40 examples x 20 000 matrices; the ill-determined ones take the SVD itself
    rng = np.random.default_rng(seed)
    S = stack(kind, 20_000, rng)
    Rt = cell_rotations_transposed(S)
    assert Rt.shape == S.shape and Rt.dtype == np.float64
    R = np.swapaxes(Rt, 1, 2)
    np.testing.assert_allclose(Rt @ R, np.broadcast_to(np.eye(3), R.shape), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, rtol=0, atol=1e-12)
    R_svd, gap = svd_rotations(S)
    determined = gap > 1e-3
    np.testing.assert_allclose(R[determined], R_svd[determined], rtol=0, atol=1e-12)
    # optimal_rotation's quaternion eigenvector is trusted to ~1e-8 (its tr(R S) to 1e-15)
    np.testing.assert_allclose(R[determined], optimal_rotation(S[determined]), rtol=0, atol=1e-8)
    # where the rotation is ill-determined, it still reaches the best trace
    scale = np.abs(S).max(axis=(1, 2))
    S_unit = S / np.where(scale > 0, scale, 1.0)[:, None, None]
    np.testing.assert_allclose(
        np.einsum("kij,kji->k", R, S_unit), np.einsum("kij,kji->k", R_svd, S_unit), rtol=0, atol=1e-12,
    )


@settings(max_examples=30, deadline=None)
@given(seeds)
def test_a_mirrored_cell_flips_the_direction_of_its_smallest_singular_value(seed):
    rng = np.random.default_rng(seed)
    # a one-ring's edges with distinct spreads, mirrored across a plane and turned: det S < 0
    E = rng.normal(size=(12, 3)) * np.array([3.0, 2.0, 1.0])
    turn = special_ortho_group.rvs(3, random_state=rng)
    S = (E.T @ (E @ MIRROR @ turn.T))[None]
    U, _, Vt = np.linalg.svd(S[0])
    assert np.linalg.det(S[0]) < 0
    np.testing.assert_allclose(cell_rotations_transposed(S)[0].T, Vt.T @ MIRROR @ U.T, rtol=0, atol=1e-12)


@settings(max_examples=10, deadline=None)
@given(meshes.filter(lambda mesh: mesh != "character"), st.sampled_from([0.0, 0.01, 0.1, 1.0]), seeds)
def test_the_polar_formula_matches_the_svd_on_arap_covariances(mesh, noise, seed):
    V, F = load_mesh(mesh)
    rng = np.random.default_rng(seed)
    S = arap_covariances(V, deformed(V, rng, noise), F, cotangent_weights(V, F))
    R_svd, gap = svd_rotations(S)
    R = np.swapaxes(cell_rotations_transposed(S), 1, 2)
    # noise 1 scrambles the mesh: a few cells' rotations are then ill-determined
    determined = gap > 1e-3
    np.testing.assert_allclose(R[determined], R_svd[determined], rtol=0, atol=1e-12)
    best = np.einsum("kij,kji->k", R_svd, S)
    np.testing.assert_allclose(np.einsum("kij,kji->k", R, S), best, rtol=0, atol=1e-12 * np.abs(S).max())
