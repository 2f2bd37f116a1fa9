import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra import numpy as hnp

from reference.shape_matching import covariance_matrix
from starter.meshes import load_mesh

coordinates = st.floats(-100, 100, allow_nan=False)
# a weight is either off or within a few orders of magnitude of the others
weights = st.one_of(st.just(0.0), st.floats(1e-3, 10))


@st.composite
def weighted_pairs(draw):
    k = draw(st.integers(1, 20))
    d = draw(st.sampled_from([2, 3]))
    P = draw(hnp.arrays(np.float64, (k, d), elements=coordinates))
    Q = draw(hnp.arrays(np.float64, (k, d), elements=coordinates))
    w = draw(hnp.arrays(np.float64, k, elements=weights))
    if w.sum() <= 0:
        w[draw(st.integers(0, k - 1))] = 1.0
    return P, Q, w


# |entries| of S are at most sum(w) * 200**2 = 20 * 10 * 4e4; rounding is relative to that
ATOL = 1e-12 * 8e6


@settings(max_examples=200)
@given(weighted_pairs())
def test_covariance_is_the_explicit_weighted_sum_of_outer_products(PQw):
    P, Q, w = PQw
    p_bar = sum(w_i * p_i for w_i, p_i in zip(w, P)) / sum(w)
    q_bar = sum(w_i * q_i for w_i, q_i in zip(w, Q)) / sum(w)
    expected = sum(w_i * np.outer(p_i - p_bar, q_i - q_bar) for w_i, p_i, q_i in zip(w, P, Q))
    S = covariance_matrix(P, Q, w)
    d = P.shape[1]
    assert S.shape == (d, d) and S.dtype == np.float64
    np.testing.assert_allclose(S, expected, rtol=1e-10, atol=ATOL)


@given(weighted_pairs())
def test_swapping_the_point_sets_transposes_the_covariance(PQw):
    P, Q, w = PQw
    np.testing.assert_allclose(covariance_matrix(Q, P, w), covariance_matrix(P, Q, w).T, rtol=1e-12, atol=ATOL)


@given(weighted_pairs(), hnp.arrays(np.float64, (2, 3), elements=coordinates))
def test_covariance_ignores_translations_of_either_set(PQw, shifts):
    P, Q, w = PQw
    d = P.shape[1]
    S = covariance_matrix(P + shifts[0, :d], Q + shifts[1, :d], w)
    np.testing.assert_allclose(S, covariance_matrix(P, Q, w), rtol=1e-9, atol=ATOL)


@given(weighted_pairs(), hnp.arrays(np.float64, (3, 3), elements=st.floats(-2, 2)))
def test_covariance_is_linear_in_the_target(PQw, A):
    P, _, w = PQw
    d = P.shape[1]
    A = A[:d, :d]
    np.testing.assert_allclose(
        covariance_matrix(P, P @ A.T, w), covariance_matrix(P, P, w) @ A.T, rtol=1e-9, atol=10 * ATOL
    )


def test_covariance_of_a_real_mesh_with_itself_is_its_scatter_matrix():
    V = load_mesh("ant")[0]
    centered = V - V.mean(axis=0)
    S = covariance_matrix(V, V)
    np.testing.assert_allclose(S, centered.T @ centered, rtol=1e-12)
    np.testing.assert_allclose(S, S.T, rtol=1e-12)


P_OK = np.arange(12.0).reshape(4, 3)


@pytest.mark.parametrize(
    "P, Q, w, message",
    [
        (P_OK, P_OK[:3], None, r"Q must have the same shape as P .* got P \(4, 3\) and Q \(3, 3\)"),
        (P_OK, P_OK[:, :2], None, r"Q must have the same shape as P .* got P \(4, 3\) and Q \(4, 2\)"),
        (P_OK[:, :2], P_OK, None, r"Q must have the same shape as P"),
        (P_OK, np.where(P_OK == 7, -np.inf, P_OK), None, "Q contains NaN or inf"),
        (np.where(P_OK == 7, np.nan, P_OK), P_OK, None, "P contains NaN or inf"),
        (P_OK, P_OK.ravel(), None, "Q must be a 2-D array"),
        (np.ones((4, 1)), np.ones((4, 1)), None, "P must have 2 or 3 columns"),
        (P_OK, P_OK, np.ones(5), r"w must have one weight per point \(4\)"),
        (P_OK, P_OK, [0.0, 0.0, -1.0, 2.0], r"w must be non-negative, got w\[2\]"),
        (P_OK, P_OK, [0.0, 0.0, 0.0, 0.0], "w must have a positive sum"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(P, Q, w, message):
    with pytest.raises(ValueError, match=message):
        covariance_matrix(P, Q, w)
