"""``k_harmonic_operator``: Q_k = (-L)(M⁻¹(-L))^(k-1), symmetric positive semi-definite, constants in its kernel."""

import igl
import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from reference.k_harmonic import k_harmonic_operator
from starter import shapes

seeds = st.integers(0, 2**32 - 1)


def _jittered_grid(seed: int, nx: int = 7, ny: int = 5):
    V, F = shapes.grid_2d(nx, ny, width=2.0, height=1.0)
    inside = np.all((V > 0) & (V < [2.0, 1.0]), axis=1)
    V[inside] += np.random.default_rng(seed).uniform(-0.3, 0.3, (int(inside.sum()), 2)) * [2.0 / nx, 1.0 / ny]
    return V, F


def _operators(V, F):
    return igl.cotmatrix(V, F), igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)


@settings(max_examples=15)
@given(seeds, st.integers(1, 3))
def test_q_k_is_the_product_of_its_k_factors_symmetric_and_positive_semidefinite(seed, k):
    V, F = _jittered_grid(seed)
    L, M = _operators(V, F)
    Q = k_harmonic_operator(L, M, k)
    assert sp.issparse(Q) and Q.shape == L.shape
    K, Mi = -L.toarray(), np.diag(1.0 / M.diagonal())
    want = K @ np.linalg.matrix_power(Mi @ K, k - 1)
    assert np.abs(Q.toarray() - want).max() <= 1e-10 * np.abs(want).max()
    assert abs(Q - Q.T).max() == 0.0
    assert np.linalg.eigvalsh(Q.toarray()).min() >= -1e-9 * np.abs(want).max()
    assert np.abs(Q @ np.ones(len(V))).max() <= 1e-9 * np.abs(want).max()


def test_dense_and_sparse_inputs_give_the_same_matrix():
    V, F = _jittered_grid(0)
    L, M = _operators(V, F)
    assert abs(k_harmonic_operator(L, M, 2) - k_harmonic_operator(L.toarray(), M.toarray(), 2)).max() == 0.0


@pytest.mark.parametrize("k", [0, -2, 1.5, True, "2"])
def test_k_that_is_not_an_integer_of_at_least_one_is_refused(k):
    V, F = _jittered_grid(0)
    with pytest.raises(ValueError, match="k must be an integer of at least 1"):
        k_harmonic_operator(*_operators(V, F), k)


def test_a_mass_matrix_that_is_not_positive_diagonal_is_refused():
    V, F = _jittered_grid(0)
    L, M = _operators(V, F)
    with pytest.raises(ValueError, match="M must be diagonal"):
        k_harmonic_operator(L, M + sp.eye(len(V), k=1), 2)
    with pytest.raises(ValueError, match="M's diagonal must be positive"):
        k_harmonic_operator(L, -M, 2)
    with pytest.raises(ValueError, match=r"M must be \(48, 48\)"):
        k_harmonic_operator(L, sp.eye(3), 2)
