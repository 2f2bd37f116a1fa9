import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp
from hypothesis import assume, given, settings, strategies as st
from hypothesis.extra import numpy as hnp
from scipy.stats import ortho_group

from reference.shape_matching import covariance_matrix, optimal_orthogonal
from starter.meshes import load_mesh

dims = st.sampled_from([2, 3])
seeds = st.integers(0, 2**32 - 1)


@st.composite
def square_matrices(draw):
    d = draw(dims)
    return draw(hnp.arrays(np.float64, (d, d), elements=st.floats(-1e3, 1e3, allow_nan=False)))


def assert_orthogonal(R):
    np.testing.assert_allclose(R.T @ R, np.eye(len(R)), rtol=0, atol=1e-12)


def assert_maximizes_trace(R, S):
    """``tr(R S)`` reaches the maximum over O(d), the sum of singular values of ``S``."""
    bound = np.linalg.svd(S, compute_uv=False).sum()
    assert np.trace(R @ S) == pytest.approx(bound, rel=1e-12, abs=1e-12 * max(bound, 1.0))


@settings(max_examples=300)
@given(square_matrices())
def test_result_is_orthogonal_and_reaches_the_sum_of_singular_values(S):
    R = optimal_orthogonal(S)
    assert R.shape == S.shape and R.dtype == np.float64
    assert_orthogonal(R)
    assert_maximizes_trace(R, S)


@given(square_matrices(), seeds)
def test_no_orthogonal_matrix_gives_a_larger_trace(S, seed):
    d = len(S)
    R = optimal_orthogonal(S)
    # Haar-random elements of O(d): rotations and reflections alike
    others = ortho_group.rvs(d, size=50, random_state=seed)
    best = np.trace(R @ S)
    assert (np.einsum("kij,ji->k", others, S) <= best + 1e-12 * max(abs(best), 1.0)).all()


@settings(max_examples=200)
@given(square_matrices())
def test_matches_the_polar_factor_when_s_is_invertible(S):
    sv = np.linalg.svd(S, compute_uv=False)
    assume(sv[-1] > 1e-6 * sv[0])
    # S = U_p H with U_p orthogonal, H positive definite; then U_p^T is the unique maximizer
    U_p, _ = scipy.linalg.polar(S)
    np.testing.assert_allclose(optimal_orthogonal(S), U_p.T, atol=1e-9 * sv[0] / sv[-1])


@given(dims, seeds)
def test_orthogonal_s_gives_its_transpose(d, seed):
    Q = ortho_group.rvs(d, random_state=seed)
    np.testing.assert_allclose(optimal_orthogonal(Q), Q.T, atol=1e-12)


def point_sets(d, kind, seed):
    """Point sets whose covariance has rank ``d - 1`` (planar), 1 (collinear) or 0 (coincident)."""
    rng = np.random.default_rng(seed)
    k = 12
    if kind == "planar":
        P = np.c_[rng.normal(size=(k, d - 1)), np.zeros(k)]
    elif kind == "collinear":
        P = np.outer(rng.normal(size=k), rng.normal(size=d))
    else:
        P = np.tile(rng.normal(size=d), (k, 1))
    rotation = ortho_group.rvs(d, random_state=rng)
    return P @ rotation.T + rng.normal(size=d)


@settings(max_examples=50)
@given(dims, st.sampled_from(["planar", "collinear", "coincident"]), seeds, seeds)
def test_rank_deficient_covariances_still_give_an_orthogonal_maximizer(d, kind, seed_p, seed_q):
    P = point_sets(d, kind, seed_p)
    Q = np.random.default_rng(seed_q).normal(size=P.shape)
    for S in (covariance_matrix(P, Q), covariance_matrix(Q, P), covariance_matrix(P, P)):
        R = optimal_orthogonal(S)
        assert_orthogonal(R)
        assert_maximizes_trace(R, S)


def test_zero_matrix_gives_an_orthogonal_matrix():
    for d in (2, 3):
        assert_orthogonal(optimal_orthogonal(np.zeros((d, d))))


def test_scatter_matrix_of_a_real_mesh_gives_the_identity():
    V = load_mesh("nut")[0]
    np.testing.assert_allclose(optimal_orthogonal(covariance_matrix(V, V)), np.eye(3), atol=1e-12)


def test_input_is_not_modified():
    S = np.array([[1.0, 2.0], [3.0, 4.0]])
    S0 = S.copy()
    optimal_orthogonal(S)
    np.testing.assert_array_equal(S, S0)


@pytest.mark.parametrize(
    "S, message",
    [
        (np.ones(3), "S must be a 2-D array"),
        (np.ones((2, 3, 3)), "S must be a 2-D array"),
        (np.ones((2, 3)), r"S must be a \(d, d\) matrix with d in \(2, 3\), got shape \(2, 3\)"),
        (np.ones((4, 4)), r"S must be a \(d, d\) matrix with d in \(2, 3\), got shape \(4, 4\)"),
        (np.ones((1, 1)), r"S must be a \(d, d\) matrix"),
        (np.array([[1.0, np.nan], [0.0, 1.0]]), "S contains NaN or inf"),
        (np.array([["a", "b"], ["c", "d"]]), "S must be a numeric array"),
        (sp.eye(3, format="csr"), "S must be a dense array"),
    ],
)
def test_bad_inputs_raise_value_error_naming_s(S, message):
    with pytest.raises(ValueError, match=message):
        optimal_orthogonal(S)
