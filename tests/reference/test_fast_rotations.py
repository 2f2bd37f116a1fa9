import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_covariances, arap_rotations
from reference.fast import fast_energy, fast_precompute, fast_rotations, rotation_clusters
from reference.linear_blend_skinning import lbs
from reference.sign_correction import optimal_rotation

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def random_transforms(rng, m, d, size):
    return np.eye(d, d + 1) + size * rng.normal(size=(m, d, d + 1))


def assert_best_rotations(R, S):
    """``R`` are rotations reaching the largest ``tr(R S)`` (any maximizer counts when ``S`` is rank-deficient)."""
    k, d, _ = S.shape
    assert R.shape == (k, d, d) and R.dtype == np.float64
    np.testing.assert_allclose(R @ R.transpose(0, 2, 1), np.broadcast_to(np.eye(d), R.shape), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, rtol=0, atol=1e-12)
    best = np.einsum("cab,cba->c", optimal_rotation(S), S)
    reached = np.einsum("cab,cba->c", R, S)
    scale = np.linalg.norm(S, axis=(1, 2))
    assert (np.abs(reached - best) <= 1e-12 * scale).all()


@settings(max_examples=25, deadline=None)
@given(meshes, st.integers(1, 30), st.floats(0.0, 1.0), seeds)
def test_each_cluster_gets_the_best_rotation_of_its_summed_arap_covariances(skinned_mesh, mesh, k, size, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    clusters = rotation_clusters(W, k, seed)
    data = fast_precompute(V, F, W, clusters, fixed)
    T = random_transforms(np.random.default_rng(seed), W.shape[1], d, size)
    S = np.zeros((k, d, d))
    np.add.at(S, clusters, arap_covariances(V, lbs(V, W, T), F, data.C))
    assert_best_rotations(fast_rotations(data, T), S)


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_with_every_vertex_its_own_cluster_it_is_the_arap_local_step_of_the_skinned_mesh(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    data = fast_precompute(V, F, W, np.arange(len(V)), fixed)
    T = random_transforms(np.random.default_rng(3), W.shape[1], d, 0.3)
    U = lbs(V, W, T)
    R = fast_rotations(data, T)
    assert_best_rotations(R, arap_covariances(V, U, F, data.C))
    expected = arap_rotations(V, U, F, data.C)
    S = arap_covariances(V, U, F, data.C)
    np.testing.assert_allclose(
        np.einsum("cab,cba->c", R, S), np.einsum("cab,cba->c", expected, S), rtol=0, atol=1e-12 * np.abs(S).max()
    )


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 20), seeds)
def test_no_other_rotations_give_a_lower_energy(skinned_mesh, mesh, k, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    data = fast_precompute(V, F, W, rotation_clusters(W, k, seed), fixed)
    T = random_transforms(rng, W.shape[1], d, 0.5)
    R = fast_rotations(data, T)
    E = fast_energy(data, T, R)
    for _ in range(3):
        other = special_ortho_group.rvs(d, size=k, random_state=rng).reshape(k, d, d)
        assert E <= fast_energy(data, T, other) + 1e-12 * abs(E)
        # the same rotations but one cluster's, turned a little
        nudged = R.copy()
        c = rng.integers(k)
        nudged[c] = special_ortho_group.rvs(d, random_state=rng) @ nudged[c]
        assert E <= fast_energy(data, T, nudged) + 1e-12 * abs(E)


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 12), seeds)
def test_a_rigid_motion_gives_its_rotation_to_every_cluster(skinned_mesh, mesh, k, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    Q = special_ortho_group.rvs(d, random_state=rng)
    data = fast_precompute(V, F, W, rotation_clusters(W, k, seed), fixed)
    R = fast_rotations(data, np.tile(np.c_[Q, rng.normal(size=d)], (W.shape[1], 1, 1)))
    np.testing.assert_allclose(R, np.broadcast_to(Q, (k, d, d)), rtol=0, atol=1e-10)


def test_inputs_are_not_modified(skinned_mesh):
    V, F, W, fixed = skinned_mesh("character")
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), fixed)
    T = np.tile(np.eye(2, 3), (5, 1, 1)) + 0.1
    copies = (T.copy(), data.covariance_operator.copy())
    fast_rotations(data, T)
    np.testing.assert_array_equal(T, copies[0])
    np.testing.assert_array_equal(data.covariance_operator, copies[1])


@pytest.mark.parametrize(
    "change, message",
    [
        ({"T": np.ones((4, 2, 3))}, r"T must have shape \(5, 2, 3\), one affine transform per handle"),
        ({"T": np.ones((5, 3, 4))}, r"T must have shape \(5, 2, 3\)"),
        ({"T": np.ones((5, 6))}, "T must be a 3-D array"),
        ({"T": np.full((5, 2, 3), np.nan)}, "T contains NaN or inf"),
        ({"data": None}, "data must be the result of fast_precompute"),
        ({"data": {"V": np.zeros((1547, 2))}}, "data must be the result of fast_precompute"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(skinned_mesh, change, message):
    V, F, W, fixed = skinned_mesh("character")
    args = {"data": fast_precompute(V, F, W, rotation_clusters(W, 4), fixed), "T": np.tile(np.eye(2, 3), (5, 1, 1))}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        fast_rotations(**args)
