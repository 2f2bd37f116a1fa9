import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra import numpy as hnp

from reference.shape_matching import centroid
from starter.meshes import load_mesh

coordinates = st.floats(-1e3, 1e3, allow_nan=False)
# a weight is either off or within a few orders of magnitude of the others
weights = st.one_of(st.just(0.0), st.floats(1e-3, 10))


@st.composite
def weighted_points(draw):
    k = draw(st.integers(1, 20))
    d = draw(st.sampled_from([2, 3]))
    P = draw(hnp.arrays(np.float64, (k, d), elements=coordinates))
    w = draw(hnp.arrays(np.float64, k, elements=weights))
    if w.sum() <= 0:
        w[draw(st.integers(0, k - 1))] = 1.0
    return P, w


@settings(max_examples=200)
@given(weighted_points())
def test_weighted_centroid_is_the_explicit_weighted_sum(Pw):
    P, w = Pw
    total = sum(w)
    expected = sum(w_i / total * p_i for w_i, p_i in zip(w, P))
    c = centroid(P, w)
    assert c.shape == (P.shape[1],) and c.dtype == np.float64
    np.testing.assert_allclose(c, expected, rtol=1e-12, atol=1e-12 * 1e3)


@given(hnp.arrays(np.float64, st.tuples(st.integers(1, 20), st.sampled_from([2, 3])), elements=coordinates))
def test_default_weights_give_the_plain_mean(P):
    np.testing.assert_allclose(centroid(P), P.mean(axis=0), rtol=1e-12, atol=1e-12 * 1e3)
    np.testing.assert_array_equal(centroid(P), centroid(P, np.ones(len(P))))


@given(weighted_points(), st.floats(1e-3, 1e3))
def test_scaling_all_weights_does_not_move_the_centroid(Pw, scale):
    P, w = Pw
    np.testing.assert_allclose(centroid(P, scale * w), centroid(P, w), rtol=1e-12, atol=1e-12 * 1e3)


@given(weighted_points(), hnp.arrays(np.float64, 3, elements=coordinates))
def test_centroid_moves_with_a_translation(Pw, t):
    P, w = Pw
    t = t[: P.shape[1]]
    np.testing.assert_allclose(centroid(P + t, w), centroid(P, w) + t, rtol=1e-12, atol=1e-9)


def test_zero_weight_points_are_ignored_on_a_real_mesh():
    V = load_mesh("ant")[0]
    keep = np.arange(len(V)) % 3 == 0
    w = np.where(keep, 1.0, 0.0)
    np.testing.assert_allclose(centroid(V, w), V[keep].mean(axis=0), rtol=1e-13, atol=1e-13)


def test_tiny_equal_weights_give_the_plain_mean_on_a_real_mesh():
    V = load_mesh("ant")[0]
    # subnormal weights: w_i * p_i alone would lose most significant bits
    np.testing.assert_allclose(centroid(V, np.full(len(V), 1e-320)), V.mean(axis=0), rtol=1e-12)


def test_inputs_are_not_modified():
    P = np.array([[0.0, 1.0], [2.0, 3.0]])
    w = np.array([1.0, 3.0])
    P0, w0 = P.copy(), w.copy()
    np.testing.assert_array_equal(centroid(P, w), [1.5, 2.5])
    np.testing.assert_array_equal(P, P0)
    np.testing.assert_array_equal(w, w0)


P_OK = np.arange(12.0).reshape(4, 3)


@pytest.mark.parametrize(
    "P, w, message",
    [
        (P_OK.ravel(), None, "P must be a 2-D array"),
        (np.zeros((4, 4)), None, "P must have 2 or 3 columns"),
        (np.zeros((0, 3)), None, "P must have at least 1 row"),
        (np.where(P_OK == 5, np.nan, P_OK), None, "P contains NaN or inf"),
        (np.full((4, 3), "a"), None, "P must be a numeric array"),
        (P_OK, [1.0, 2.0, 3.0], r"w must have one weight per point \(4\), got 3"),
        (P_OK, [1.0, -2.0, 3.0, 1.0], r"w must be non-negative, got w\[1\] = -2"),
        (P_OK, np.zeros(4), "w must have a positive sum"),
        (P_OK, [1.0, np.inf, 3.0, 1.0], "w contains NaN or inf"),
        (P_OK, np.ones((4, 1)), "w must be a 1-D array"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(P, w, message):
    with pytest.raises(ValueError, match=message):
        centroid(P, w)
