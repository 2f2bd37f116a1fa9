"""``k_harmonic_precompute``: bad handles and a singular free block are refused; one precomputation serves many solves."""

import numpy as np
import pytest
import scipy.sparse as sp

from reference.k_harmonic import k_harmonic_precompute, k_harmonic_solve

# -L of a path 0 - 1 - 2 - 3 with unit weights
PATH = sp.csr_matrix(np.array([[1.0, -1, 0, 0], [-1, 2, -1, 0], [0, -1, 2, -1], [0, 0, -1, 1]]))


@pytest.mark.parametrize(("handles", "message"), [
    ([], "non-empty"), ([0, 0], "repeats a vertex"), ([0, 4], "0..3"), ([-1, 2], "0..3"), ([[0], [3]], "1D"),
])
def test_bad_handles_are_refused_naming_the_problem(handles, message):
    with pytest.raises(ValueError, match=message):
        k_harmonic_precompute(PATH, np.array(handles, dtype=np.int64))


def test_a_component_without_a_handle_is_refused():
    two_paths = sp.block_diag([PATH, PATH]).tocsr()
    with pytest.raises(ValueError, match="singular"):
        k_harmonic_precompute(two_paths, np.array([0, 3]))


def test_one_precomputation_serves_many_solves_with_handles_in_any_order():
    data = k_harmonic_precompute(PATH, np.array([3, 0]))
    assert np.allclose(k_harmonic_solve(data, [[3.0], [0.0]]).ravel(), [0, 1, 2, 3])
    assert np.allclose(k_harmonic_solve(data, [[0.0], [6.0]]).ravel(), [6, 4, 2, 0])
    every = k_harmonic_precompute(PATH, np.arange(4))
    assert np.array_equal(k_harmonic_solve(every, np.eye(4)), np.eye(4))
