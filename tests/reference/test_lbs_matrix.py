import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.distance import cdist

from reference.linear_blend_skinning import lbs_matrix
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)


def inverse_distance_weights(V, m, rng):
    """Partition-of-unity weights for ``m`` random handle points in the bounding box."""
    lo, hi = V.min(axis=0), V.max(axis=0)
    handles = rng.uniform(lo, hi, size=(m, V.shape[1]))
    W = cdist(V, handles) ** -2.0
    return W / W.sum(axis=1, keepdims=True)


@settings(max_examples=20, deadline=None)
@given(st.sampled_from(["bar_coarse", "character"]), st.integers(1, 6), seeds)
def test_equals_igl_lbs_matrix_exactly_on_real_meshes(mesh, m, seed):
    V = load_mesh(mesh)[0]
    W = inverse_distance_weights(V, m, np.random.default_rng(seed))
    M = lbs_matrix(V, W)
    n, d = V.shape
    assert M.shape == (n, m * (d + 1)) and M.dtype == np.float64
    np.testing.assert_array_equal(M, igl.lbs_matrix(V, W))


@given(st.sampled_from([2, 3]), st.integers(1, 5), st.integers(1, 5), seeds)
def test_entries_follow_the_contract_layout(d, n, m, seed):
    rng = np.random.default_rng(seed)
    V = rng.normal(size=(n, d))
    W = rng.normal(size=(n, m))
    M = lbs_matrix(V, W)
    for i in range(n):
        v_h = [*V[i], 1.0]
        for j in range(m):
            for c in range(d + 1):
                assert M[i, j * (d + 1) + c] == W[i, j] * v_h[c]


def test_inputs_are_not_modified():
    V = load_mesh("bar_coarse")[0]
    W = inverse_distance_weights(V, 3, np.random.default_rng(0))
    V0, W0 = V.copy(), W.copy()
    lbs_matrix(V, W)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(W, W0)


V_OK = np.arange(12.0).reshape(4, 3)
W_OK = np.full((4, 2), 0.5)


@pytest.mark.parametrize(
    "V, W, message",
    [
        (V_OK, W_OK[:3], r"W must have shape \(4, m\), one row per vertex of V .* got \(3, 2\)"),
        (V_OK, np.zeros((4, 0)), r"W must have shape \(4, m\), .*m >= 1 .* got \(4, 0\)"),
        (V_OK, W_OK.ravel(), "W must be a 2-D array"),
        (V_OK, np.where(W_OK > 0, np.nan, 0.0), "W contains NaN or inf"),
        (V_OK, np.full((4, 2), "w"), "W must be a numeric array"),
        (np.zeros((4, 4)), W_OK, "V must have 2 or 3 columns"),
        (np.where(V_OK == 3, np.inf, V_OK), W_OK, "V contains NaN or inf"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, W, message):
    with pytest.raises(ValueError, match=message):
        lbs_matrix(V, W)
