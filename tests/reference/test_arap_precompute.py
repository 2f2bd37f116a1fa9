import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from starter.meshes import load_mesh
from reference.arap import arap_covariances, arap_precompute, cotangent_laplacian, cotangent_weights

seeds = st.integers(0, 2**32 - 1)


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_splits_the_vertices_into_handles_and_free_ones(mesh_and_handles, mesh):
    V, F, handles = mesh_and_handles(mesh)
    shuffled = np.random.default_rng(0).permutation(handles)
    data = arap_precompute(V, F, shuffled)
    np.testing.assert_array_equal(data.handles, shuffled)
    np.testing.assert_array_equal(data.free, np.setdiff1d(np.arange(len(V)), handles))
    np.testing.assert_array_equal(data.V, V)
    np.testing.assert_array_equal(data.F, F)
    np.testing.assert_allclose(data.C, cotangent_weights(V, F), rtol=0, atol=0)
    assert abs(data.L - cotangent_laplacian(V, F)).max() == 0.0


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_the_factorization_solves_the_reduced_laplacian_system(mesh_and_handles, mesh):
    V, F, handles = mesh_and_handles(mesh)
    data = arap_precompute(V, F, handles)
    A = -data.L[data.free][:, data.free]
    b = np.random.default_rng(1).normal(size=(len(data.free), V.shape[1]))
    x = data.solver.solve(b)
    np.testing.assert_allclose(A @ x, b, rtol=0, atol=1e-10 * np.abs(b).max())
    assert abs(data.L_free_handles - data.L[data.free][:, data.handles]).max() == 0.0


@settings(max_examples=20, deadline=None)
@given(st.sampled_from(["bar_coarse", "character"]), seeds)
def test_the_covariance_operator_reproduces_arap_covariances(mesh_and_handles, mesh, seed):
    V, F, handles = mesh_and_handles(mesh)
    n, d = V.shape
    data = arap_precompute(V, F, handles)
    U = V + 0.2 * np.random.default_rng(seed).normal(size=V.shape)
    S = (data.covariance_operator @ U).reshape(n, d, d)
    np.testing.assert_allclose(S, arap_covariances(V, U, F, data.C), rtol=0, atol=1e-13)


@settings(max_examples=20, deadline=None)
@given(st.sampled_from(["bar_coarse", "character"]), seeds)
def test_the_rhs_operator_is_the_gradient_of_the_rotation_term(mesh_and_handles, mesh, seed):
    # Σ_i tr(R_i S_i(U)) = tr(Uᵀ B) with B = Gᵀ R; rhs_operator holds the free rows of B / 3
    V, F, handles = mesh_and_handles(mesh)
    n, d = V.shape
    data = arap_precompute(V, F, handles)
    rng = np.random.default_rng(seed)
    U = rng.normal(size=V.shape)
    U[handles] = 0.0
    R = special_ortho_group.rvs(d, size=n, random_state=rng)
    b = data.rhs_operator @ R.transpose(0, 2, 1).reshape(n * d, d)
    assert b.shape == (len(data.free), d)
    rotation_term = np.einsum("kij,kji->", R, arap_covariances(V, U, F, data.C))
    assert 3.0 * np.sum(U[data.free] * b) == pytest.approx(rotation_term, rel=1e-11)


def test_the_rest_dirichlet_energy_is_stored(mesh_and_handles):
    V, F, handles = mesh_and_handles("bar_coarse")
    data = arap_precompute(V, F, handles)
    assert data.rest_dirichlet == pytest.approx(-np.sum(V * (cotangent_laplacian(V, F) @ V)), rel=1e-12)


def test_every_vertex_may_be_a_handle():
    V, F = load_mesh("bar_coarse")
    data = arap_precompute(V, F, np.arange(len(V)))
    assert data.free.size == 0 and data.solver is None


def test_inputs_are_not_modified(mesh_and_handles):
    V, F, handles = mesh_and_handles("bar_coarse")
    copies = [a.copy() for a in (V, F, handles)]
    arap_precompute(V, F, handles)
    for a, b in zip((V, F, handles), copies):
        np.testing.assert_array_equal(a, b)


def two_bars():
    V, F = load_mesh("bar_coarse")
    return np.vstack([V, V + [10.0, 0.0, 0.0]]), np.vstack([F, F + len(V)]), len(V)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"handles": np.array([452])}, r"handles\[0\] = 452 is out of range"),
        ({"handles": np.array([-1, 3])}, r"handles\[0\] = -1 is out of range"),
        ({"handles": np.array([3, 5, 3])}, "handles has duplicate vertex 3"),
        ({"handles": np.array([], dtype=np.int64)}, "handles is empty"),
        ({"handles": np.array([[0, 1]])}, "handles must be a 1-D array"),
        ({"handles": np.array([0.0, 1.0])}, "handles must be an integer array"),
        ({"V": np.full((452, 3), np.nan)}, "V contains NaN or inf"),
        ({"V": np.ones((452, 4))}, "V must have 2 or 3 columns"),
        ({"F": np.array([[0, 1, 2], [0, 1, 1]])}, "F has a triangle with a repeated vertex"),
        ({"F": np.array([[0, 1, 500]])}, "F has a vertex index out of range"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(mesh_and_handles, change, message):
    V, F, handles = mesh_and_handles("bar_coarse")
    args = {"V": V, "F": F, "handles": handles}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        arap_precompute(**args)


def test_zero_area_triangles_are_rejected(mesh_and_handles):
    V, F, handles = mesh_and_handles("bar_coarse")
    V = V.copy()
    V[F[0, 2]] = V[F[0, 0]]
    with pytest.raises(ValueError, match="F has a zero-area triangle"):
        arap_precompute(V, F, handles)


def test_every_connected_component_needs_a_handle():
    V, F, n = two_bars()
    with pytest.raises(ValueError, match="handles must include a vertex of every connected component"):
        arap_precompute(V, F, np.array([0, 1, 2]))
    data = arap_precompute(V, F, np.array([0, n]))
    assert sp.issparse(data.L) and data.free.size == 2 * n - 2
