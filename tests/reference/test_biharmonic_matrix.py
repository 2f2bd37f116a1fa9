import igl
import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from reference.bounded_biharmonic_weights import biharmonic_matrix
from starter.meshes import load_mesh

MESHES = ["character", "disc_with_holes", "bar_coarse", "torus", "sphere"]
seeds = st.integers(0, 2**32 - 1)


@pytest.mark.parametrize("mesh", MESHES)
def test_equals_l_inverse_mass_l_from_libigl(mesh):
    V, F = load_mesh(mesh)
    Q = biharmonic_matrix(V, F)
    L = igl.cotmatrix(V, F)
    M = igl.massmatrix(V, F)
    expected = L @ sp.diags(1.0 / M.diagonal()) @ L
    assert sp.issparse(Q) and Q.shape == (len(V), len(V))
    assert abs(Q - expected).max() <= 1e-12 * abs(expected).max()


@pytest.mark.parametrize("mesh", ["bar_tet", "hand_tet"])
def test_tetrahedra_give_l_inverse_barycentric_mass_l_from_libigl(mesh):
    V, T = load_mesh(mesh)
    V = V + 0.005 * np.random.default_rng(0).uniform(-1, 1, V.shape)
    Q = biharmonic_matrix(V, T)
    L = igl.cotmatrix(V, T)
    M = igl.massmatrix(V, T)  # barycentric: libigl's default on tetrahedra, and what igl.bbw uses
    expected = L @ sp.diags(1.0 / M.diagonal()) @ L
    assert abs(Q - expected).max() <= 1e-9 * abs(expected).max()
    scale = abs(Q).max()
    assert abs(Q - Q.T).max() <= 1e-14 * scale
    assert np.abs(Q @ np.ones(len(V))).max() <= 1e-10 * scale


@pytest.mark.parametrize("mesh", MESHES)
def test_symmetric_with_constants_in_the_null_space(mesh):
    V, F = load_mesh(mesh)
    Q = biharmonic_matrix(V, F)
    scale = abs(Q).max()
    assert abs(Q - Q.T).max() <= 1e-14 * scale
    np.testing.assert_allclose(Q @ np.ones(len(V)), 0.0, atol=1e-12 * scale)


@settings(max_examples=20, deadline=None)
@given(st.sampled_from(MESHES), seeds)
def test_quadratic_form_is_the_mass_weighted_squared_laplacian(mesh, seed):
    V, F = load_mesh(mesh)
    x = np.random.default_rng(seed).normal(size=len(V))
    Lx = igl.cotmatrix(V, F) @ x
    mass = igl.massmatrix(V, F).diagonal()
    energy = np.sum(Lx**2 / mass)
    # Q is positive semi-definite: xᵀQx = ‖M^-½ L x‖² ≥ 0
    assert energy >= 0
    assert x @ (biharmonic_matrix(V, F) @ x) == pytest.approx(energy, rel=1e-10)


def test_smallest_eigenvalue_is_zero_and_the_next_positive():
    V, F = load_mesh("bar_coarse")
    eigenvalues = np.linalg.eigvalsh(biharmonic_matrix(V, F).toarray())
    scale = eigenvalues[-1]
    assert abs(eigenvalues[0]) <= 1e-10 * scale
    # a connected mesh: only the constants are in the null space
    assert eigenvalues[1] > 1e-8 * scale


def test_inputs_are_not_modified():
    V, F = load_mesh("character")
    V0, F0 = V.copy(), F.copy()
    biharmonic_matrix(V, F)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)


@pytest.mark.parametrize(
    "V, F, message",
    [
        (np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), np.array([[0, 1, 2]]), "F has a zero-area triangle"),
        (np.eye(3), np.array([[0, 1, 3]]), "F has a vertex index out of range"),
        (np.ones((3, 4)), np.array([[0, 1, 2]]), "V must have 2 or 3 columns"),
        (np.eye(3), np.array([[0, 1, 2, 0, 1]]), r"F must have shape \(f, 3\) \(triangles\) or \(f, 4\)"),
        (np.eye(3), np.array([[0, 1, 2, 0]]), r"F has a tetrahedron with a repeated vertex: F\[0\]"),
        (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]), np.array([[0, 1, 2, 3]]), r"F has a flat tetrahedron"),
        (np.eye(4)[:, :2], np.array([[0, 1, 2, 3]]), r"V must have shape \(n, 3\) for a tetrahedral mesh"),
        (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "F must be an integer array"),
        (np.array([[0.0, 0.0], [1.0, 0.0], [0.0, np.nan]]), np.array([[0, 1, 2]]), "V contains NaN or inf"),
        (np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [5.0, 5.0]]), np.array([[0, 1, 2]]), r"V has an unreferenced vertex: V\[3\]"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, F, message):
    with pytest.raises(ValueError, match=message):
        biharmonic_matrix(V, F)
