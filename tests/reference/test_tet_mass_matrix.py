import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import tet_mass_matrix, tet_volumes

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=15, deadline=None)
@given(seed=seeds, name=st.sampled_from(["bar_tet", "hand_tet"]))
def test_mass_is_diagonal_equals_igl_and_sums_to_the_volume(tet_mesh, seed, name):
    V, T = tet_mesh(name, seed)
    M = tet_mass_matrix(V, T)
    assert M.shape == (len(V), len(V)) and M.nnz == len(V)
    assert M.diagonal().min() > 0
    assert M.sum() == pytest.approx(tet_volumes(V, T).sum(), rel=1e-12)
    assert abs(M - igl.massmatrix(V, T)).max() <= 1e-15
    assert abs(M - igl.massmatrix(V, T, igl.MASSMATRIX_TYPE_BARYCENTRIC)).max() <= 1e-15


def test_an_inverted_tetrahedron_still_has_positive_mass():
    V = np.eye(4)[:, :3]
    np.testing.assert_allclose(tet_mass_matrix(V, [[0, 2, 1, 3]]).diagonal(), np.full(4, 1 / 24))
