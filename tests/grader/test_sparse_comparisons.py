"""Sparse outputs are checked without densifying them, with the verdicts and messages of dense ones."""

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from grader.checks.base import ShapeError, as_array, as_matrix, close, max_abs


@st.composite
def matrix_pairs(draw):
    n, m = draw(st.integers(1, 9)), draw(st.integers(1, 9))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    a = sp.random(n, m, density=draw(st.floats(0.0, 1.0)), random_state=rng, format="csr")
    b = a.copy()
    b.data = b.data + rng.normal(0, draw(st.sampled_from([0.0, 1e-12, 1e-3, 1.0])), b.nnz)
    return a, (b + sp.random(n, m, density=draw(st.floats(0.0, 0.3)), random_state=rng)).tocsr()


@settings(max_examples=200, deadline=None)
@given(matrix_pairs(), st.sampled_from([1e-9, 1e-3, 1.0]))
def test_sparse_and_dense_matrices_get_the_same_verdict_and_the_same_worst_entry(pair, tol):
    a, b = pair
    dense_ok, dense_where = close(a.toarray(), b.toarray(), tol, max_abs(b.toarray()))
    sparse_ok, sparse_where = close(a, b, tol, max_abs(b))
    assert sparse_ok == dense_ok
    largest = np.abs(a.toarray() - b.toarray())
    if largest.max() > 0 and np.sum(largest == largest.max()) == 1:  # a unique worst entry: same place named
        assert sparse_where == dense_where


def test_a_sparse_output_keeps_its_entries_and_is_not_densified():
    n = 20_000  # 3.2 GB dense
    L = sp.diags([np.full(n - 1, -1.0), np.full(n, 2.0), np.full(n - 1, -1.0)], [-1, 0, 1], format="coo")
    got = as_matrix(L, (n, n), "L")
    assert sp.isspmatrix_csr(got) and got.nnz == 3 * n - 2
    assert close(got, L.tocsr(), 1e-12)[0] and not close(got, 2 * L.tocsr(), 1e-12)[0]
    off_diagonal = got - sp.diags(got.diagonal())
    assert not close(off_diagonal, 0.0, 1e-12)[0]  # against a scalar zero, as "M is diagonal" asks
    assert close(off_diagonal.multiply(0.0), 0.0, 1e-12) == (True, "largest difference 0 at index (0, 0)")


def test_a_sparse_output_is_refused_as_a_dense_one_would_be():
    bad = sp.csr_matrix(np.array([[1.0, 0.0], [0.0, np.nan]]))
    with pytest.raises(ShapeError, match=r"first at index \(1, 1\)"):
        as_matrix(bad, (2, 2), "L")
    with pytest.raises(ShapeError, match=r"first at index \(1, 1\)"):
        as_array(bad.toarray(), (2, 2), "L")
    with pytest.raises(ShapeError, match=r"L should have shape \(2, 2\), got \(2, 3\)"):
        as_matrix(sp.csr_matrix((2, 3)), (2, 2), "L")
    with pytest.raises(ShapeError, match=r"L should have shape \(2, 2\), got \(2, 3\)"):
        as_array(np.zeros((2, 3)), (2, 2), "L")
