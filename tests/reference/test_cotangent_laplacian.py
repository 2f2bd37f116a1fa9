import igl
import igl.triangle
import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from reference.arap import cotangent_laplacian, cotangent_weights
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "bar", "torus", "nut", "character", "disc_with_holes"])


def triangulated_square_with_hole(max_area=0.002):
    """A 2D mesh straight from Triangle: the unit square minus a square hole."""
    outer = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    inner = 0.5 + 0.2 * (outer - 0.5)
    loop = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])
    V, F, *_ = igl.triangle.triangulate(
        np.vstack([outer, inner]), np.vstack([loop, loop + 4]), np.array([[0.5, 0.5]]), flags=f"pq30a{max_area}Q"
    )
    return V, F


def interior_vertices(F, n):
    """Vertices not on the boundary."""
    boundary = np.zeros(n, dtype=bool)
    for loop in igl.boundary_loop_all(F):
        boundary[loop] = True
    return np.flatnonzero(~boundary)


@pytest.mark.parametrize("mesh", ["bar", "bar_coarse", "torus", "nut", "sphere", "character", "disc_with_holes"])
def test_equals_igl_cotmatrix(mesh):
    V, F = load_mesh(mesh)
    L = cotangent_laplacian(V, F)
    assert sp.issparse(L) and L.shape == (len(V), len(V))
    scale = np.abs(L).max()
    assert abs(L - igl.cotmatrix(V, F)).max() < 1e-12 * max(scale, 1.0)


def test_equals_igl_cotmatrix_on_a_fresh_triangle_mesh():
    V, F = triangulated_square_with_hole()
    assert abs(cotangent_laplacian(V, F) - igl.cotmatrix(V, F)).max() < 1e-12


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_quadratic_form_is_minus_the_weighted_sum_of_squared_edge_differences(mesh, seed):
    V, F = load_mesh(mesh)
    L = cotangent_laplacian(V, F)
    C = cotangent_weights(V, F)
    x = np.random.default_rng(seed).normal(size=len(V))
    diff = x[np.roll(F, -1, axis=1)] - x[np.roll(F, -2, axis=1)]
    dirichlet = np.sum(C * diff**2)
    assert -x @ (L @ x) == pytest.approx(dirichlet, rel=1e-10)
    # the Dirichlet energy of a piecewise linear function is never negative
    assert dirichlet >= 0


@pytest.mark.parametrize("mesh", ["bar_coarse", "torus", "character", "disc_with_holes"])
def test_symmetric_with_zero_row_sums(mesh):
    V, F = load_mesh(mesh)
    L = cotangent_laplacian(V, F)
    assert abs(L - L.T).max() == 0.0
    np.testing.assert_allclose(np.asarray(L.sum(axis=1)).ravel(), 0.0, atol=1e-12 * np.abs(L).max())


def test_linear_functions_are_harmonic_at_the_interior_of_planar_meshes():
    for V, F in (load_mesh("character"), load_mesh("disc_with_holes"), triangulated_square_with_hole()):
        L = cotangent_laplacian(V, F)
        inside = interior_vertices(F, len(V))
        assert inside.size > 0
        np.testing.assert_allclose((L @ V)[inside], 0.0, atol=1e-12)


def test_inputs_are_not_modified():
    V, F = load_mesh("character")
    V0, F0 = V.copy(), F.copy()
    cotangent_laplacian(V, F)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)


@pytest.mark.parametrize(
    "V, F, message",
    [
        (np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), np.array([[0, 1, 2]]), "F has a zero-area triangle"),
        (np.eye(3), np.array([[0, 1, 3]]), "F has a vertex index out of range"),
        (np.ones((3, 4)), np.array([[0, 1, 2]]), "V must have 2 or 3 columns"),
        (np.eye(3), np.array([[0, 1, 2, 0]]), r"F must have shape \(f, 3\)"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, F, message):
    with pytest.raises(ValueError, match=message):
        cotangent_laplacian(V, F)
