import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.distance import cdist, pdist
from scipy.stats import ortho_group

from reference.linear_blend_skinning import lbs, lbs_matrix
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def inverse_distance_weights(V, m, rng):
    """Partition-of-unity weights for ``m`` random handle points in the bounding box."""
    handles = rng.uniform(V.min(axis=0), V.max(axis=0), size=(m, V.shape[1]))
    W = cdist(V, handles) ** -2.0
    return W / W.sum(axis=1, keepdims=True)


def identity_transforms(m, d):
    return np.tile(np.eye(d, d + 1), (m, 1, 1))


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 6), seeds)
def test_identity_transforms_leave_the_mesh_at_rest(mesh, m, seed):
    V = load_mesh(mesh)[0]
    W = inverse_distance_weights(V, m, np.random.default_rng(seed))
    U = lbs(V, W, identity_transforms(m, V.shape[1]))
    assert U.shape == V.shape and U.dtype == np.float64
    np.testing.assert_allclose(U, V, rtol=0, atol=1e-12 * np.abs(V).max())


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 6), st.booleans(), seeds)
def test_one_rigid_transform_for_all_handles_moves_the_mesh_rigidly(mesh, m, reflect, seed):
    rng = np.random.default_rng(seed)
    V = load_mesh(mesh)[0]
    n, d = V.shape
    W = inverse_distance_weights(V, m, rng)
    R = ortho_group.rvs(d, random_state=rng)
    if (np.linalg.det(R) < 0) != reflect:
        R[:, 0] *= -1
    t = rng.uniform(-10, 10, size=d)
    U = lbs(V, W, np.tile(np.c_[R, t], (m, 1, 1)))
    scale = np.abs(V).max() + 10
    np.testing.assert_allclose(U, V @ R.T + t, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(pdist(U), pdist(V), rtol=0, atol=1e-12 * scale)


@settings(max_examples=30, deadline=None)
@given(meshes, st.integers(1, 6), seeds)
def test_lbs_equals_the_skinning_matrix_times_the_stacked_transposed_transforms(mesh, m, seed):
    rng = np.random.default_rng(seed)
    V = load_mesh(mesh)[0]
    d = V.shape[1]
    # any weights and any affine transforms, not only partitions of unity and rigid maps
    W = rng.normal(size=(len(V), m))
    T = rng.normal(size=(m, d, d + 1))
    T_stack = np.vstack([T_j.T for T_j in T])
    expected = lbs_matrix(V, W) @ T_stack
    np.testing.assert_allclose(lbs(V, W, T), expected, rtol=0, atol=1e-12 * np.abs(expected).max())


@given(st.sampled_from([2, 3]), st.integers(1, 5), seeds)
def test_vertex_bound_to_one_handle_follows_that_handle_exactly(d, m, seed):
    rng = np.random.default_rng(seed)
    V = rng.normal(size=(m, d))
    T = rng.normal(size=(m, d, d + 1))
    # vertex i is bound to handle m-1-i only
    W = np.eye(m)[::-1]
    U = lbs(V, W, T)
    for i in range(m):
        A, t = T[m - 1 - i, :, :d], T[m - 1 - i, :, d]
        np.testing.assert_allclose(U[i], A @ V[i] + t, rtol=1e-14, atol=1e-14)


def test_inputs_are_not_modified():
    V = load_mesh("bar_coarse")[0]
    W = inverse_distance_weights(V, 2, np.random.default_rng(1))
    T = np.random.default_rng(2).normal(size=(2, 3, 4))
    copies = V.copy(), W.copy(), T.copy()
    lbs(V, W, T)
    for before, after in zip(copies, (V, W, T)):
        np.testing.assert_array_equal(before, after)


V_OK = np.arange(12.0).reshape(4, 3)
W_OK = np.full((4, 2), 0.5)
T_OK = identity_transforms(2, 3)


@pytest.mark.parametrize(
    "V, W, T, message",
    [
        (V_OK, W_OK, identity_transforms(3, 3), r"T must have shape \(2, 3, 4\), one affine transform per column of W, got \(3, 3, 4\)"),
        (V_OK, W_OK, identity_transforms(2, 2), r"T must have shape \(2, 3, 4\).* got \(2, 2, 3\)"),
        (V_OK, W_OK, T_OK[:, :, :3], r"T must have shape \(2, 3, 4\).* got \(2, 3, 3\)"),
        (V_OK, W_OK, T_OK[0], "T must be a 3-D array"),
        (V_OK, W_OK, np.where(T_OK == 1, np.nan, T_OK), "T contains NaN or inf"),
        (V_OK, W_OK, np.full((2, 3, 4), "t"), "T must be a numeric array"),
        (V_OK, W_OK[:3], T_OK, r"W must have shape \(4, m\), one row per vertex of V .* got \(3, 2\)"),
        (V_OK, np.zeros((4, 0)), T_OK[:0], r"W must have shape \(4, m\)"),
        (V_OK, W_OK.ravel(), T_OK, "W must be a 2-D array"),
        (V_OK, np.where(W_OK > 0, -np.inf, 0.0), T_OK, "W contains NaN or inf"),
        (V_OK[:, :1], W_OK, T_OK, "V must have 2 or 3 columns"),
        (V_OK[:0], W_OK[:0], T_OK, "V must have at least 1 row"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, W, T, message):
    with pytest.raises(ValueError, match=message):
        lbs(V, W, T)
