import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.arap import arap_global_step, arap_precompute, cotangent_laplacian, laplacian_editing

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_is_the_global_step_with_identity_rotations(mesh_and_handles, mesh, seed):
    V, F, handles = mesh_and_handles(mesh)
    n, d = V.shape
    target = V[handles] + 0.3 * np.random.default_rng(seed).normal(size=(len(handles), d))
    U = laplacian_editing(V, F, handles, target)
    np.testing.assert_array_equal(U[handles], target)
    expected = arap_global_step(arap_precompute(V, F, handles), np.tile(np.eye(d), (n, 1, 1)), target)
    # CHOLMOD's supernodal solves may round differently from one factorization to the next (~1e-14)
    np.testing.assert_allclose(U, expected, rtol=0, atol=1e-12 * max(1.0, np.abs(expected).max()))


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_the_displacement_is_harmonic_at_the_free_vertices(mesh_and_handles, mesh, seed):
    # minimizing Σ C ‖(u_j - u_k) - (v_j - v_k)‖² makes L (U - V) vanish off the handles
    V, F, handles = mesh_and_handles(mesh)
    target = V[handles] + np.random.default_rng(seed).normal(size=(len(handles), V.shape[1]))
    U = laplacian_editing(V, F, handles, target)
    free = np.setdiff1d(np.arange(len(V)), handles)
    L = cotangent_laplacian(V, F)
    np.testing.assert_allclose((L @ (U - V))[free], 0.0, atol=1e-10 * np.abs(U - V).max())


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_translated_handles_translate_the_mesh(mesh_and_handles, mesh, seed):
    V, F, handles = mesh_and_handles(mesh)
    t = np.random.default_rng(seed).normal(size=V.shape[1])
    np.testing.assert_allclose(laplacian_editing(V, F, handles, V[handles] + t), V + t, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"handles": np.array([0, 0])}, "handles has duplicate vertex 0"),
        ({"handles": np.array([], dtype=np.int64)}, "handles is empty"),
        ({"handle_positions": np.ones((3, 3))}, r"handle_positions must have shape \(72, 3\)"),
        ({"F": np.array([[0, 1, 1]])}, "F has a triangle with a repeated vertex"),
        ({"V": np.ones((452, 1))}, "V must have 2 or 3 columns"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(mesh_and_handles, change, message):
    V, F, handles = mesh_and_handles("bar_coarse")
    args = {"V": V, "F": F, "handles": handles, "handle_positions": V[handles]}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        laplacian_editing(**args)
