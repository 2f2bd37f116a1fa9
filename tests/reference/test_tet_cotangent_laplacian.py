import igl
import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import tet_cotangent_laplacian, tet_mass_matrix

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=15, deadline=None)
@given(seed=seeds, name=st.sampled_from(["bar_tet", "hand_tet"]))
def test_laplacian_equals_igl_cotmatrix_symmetric_rows_summing_to_zero(tet_mesh, seed, name):
    V, T = tet_mesh(name, seed)
    L = tet_cotangent_laplacian(V, T)
    assert sp.issparse(L) and L.shape == (len(V), len(V))
    scale = abs(L).max()
    assert abs(L - L.T).max() <= 1e-14 * scale
    assert np.abs(L @ np.ones(len(V))).max() <= 1e-12 * scale
    assert abs(L - igl.cotmatrix(V, T)).max() <= 1e-9 * scale


@settings(max_examples=15, deadline=None)
@given(seed=seeds)
def test_linear_functions_are_harmonic_inside_and_the_dirichlet_energy_is_exact(tet_mesh, seed):
    V, T = tet_mesh("bar_tet", seed)
    L = tet_cotangent_laplacian(V, T)
    a = np.random.default_rng(seed).standard_normal(3)
    u = V @ a
    # (L u)_i = -a · ∫ ∇φ_i, zero unless φ_i reaches the boundary
    inside = ~np.isin(np.arange(len(V)), igl.boundary_facets(T)[0])
    assert np.abs((L @ u)[inside]).max() <= 1e-10 * np.abs(a).max()
    # -uᵀ L u = ∫ ‖∇u‖² = ‖a‖² · volume for a linear u
    assert -u @ (L @ u) == pytest.approx(a @ a * tet_mass_matrix(V, T).sum(), rel=1e-10)


def test_minus_laplacian_is_positive_semidefinite_with_the_constants_as_kernel(tet_mesh):
    V, T = tet_mesh("bar_tet")
    K = -tet_cotangent_laplacian(V, T).toarray()
    eigenvalues = np.linalg.eigvalsh(K)
    assert abs(eigenvalues[0]) <= 1e-12 * eigenvalues[-1]
    assert eigenvalues[1] > 1e-4 * eigenvalues[-1] / len(V)
