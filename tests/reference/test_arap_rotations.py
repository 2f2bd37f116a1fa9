import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_covariances, arap_energy, arap_rotations, cotangent_weights
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
