import types

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from starter.meshes import load_mesh
from reference.arap import arap_energy, arap_global_step, arap_precompute, arap_rotations

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_the_result_minimizes_the_energy_for_the_given_rotations(mesh_and_handles, mesh, seed):
    V, F, handles = mesh_and_handles(mesh)
    data = arap_precompute(V, F, handles)
    rng = np.random.default_rng(seed)
    R = arap_rotations(V, V + 0.1 * rng.normal(size=V.shape), F, data.C)
    target = V[handles] + 0.2 * rng.normal(size=(len(handles), V.shape[1]))
    U = arap_global_step(data, R, target)
    assert U.shape == V.shape and U.dtype == np.float64
    np.testing.assert_array_equal(U[handles], target)
    E = arap_energy(V, U, F, data.C, R)
    for scale in (1e-3, 1e-1):
        D = scale * rng.normal(size=V.shape)
        D[handles] = 0.0
        plus, minus = arap_energy(V, U + D, F, data.C, R), arap_energy(V, U - D, F, data.C, R)
        # E is quadratic in U: E(U ± D) = E(U) ± ∇E·D + DᵀHD, so a zero gradient at
        # the free vertices makes both sides equal, and both rise above E(U)
        curvature = plus + minus - 2.0 * E
        assert curvature > 0
        assert abs(plus - minus) <= 1e-6 * curvature


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_rigidly_moved_handles_and_rotations_move_the_whole_mesh_rigidly(mesh_and_handles, mesh, seed):
    V, F, handles = mesh_and_handles(mesh)
    n, d = V.shape
    data = arap_precompute(V, F, handles)
    rng = np.random.default_rng(seed)
    Q, t = special_ortho_group.rvs(d, random_state=rng), rng.normal(size=d)
    U = arap_global_step(data, np.broadcast_to(Q, (n, d, d)), V[handles] @ Q.T + t)
    np.testing.assert_allclose(U, V @ Q.T + t, rtol=0, atol=1e-10)


def test_identity_rotations_and_handles_at_rest_give_the_rest_pose(mesh_and_handles):
    for mesh in ("bar_coarse", "character"):
        V, F, handles = mesh_and_handles(mesh)
        n, d = V.shape
        U = arap_global_step(arap_precompute(V, F, handles), np.tile(np.eye(d), (n, 1, 1)), V[handles])
        np.testing.assert_allclose(U, V, rtol=0, atol=1e-12)


def test_with_every_vertex_a_handle_the_handles_are_the_answer():
    V, F = load_mesh("bar_coarse")
    order = np.random.default_rng(0).permutation(len(V))
    target = V[order] + 1.0
    U = arap_global_step(arap_precompute(V, F, order), np.tile(np.eye(3), (len(V), 1, 1)), target)
    np.testing.assert_array_equal(U[order], target)


def test_inputs_are_not_modified(mesh_and_handles):
    V, F, handles = mesh_and_handles("bar_coarse")
    data = arap_precompute(V, F, handles)
    R = np.tile(np.eye(3), (len(V), 1, 1))
    target = V[handles] + 0.1
    copies = (R.copy(), target.copy())
    arap_global_step(data, R, target)
    np.testing.assert_array_equal(R, copies[0])
    np.testing.assert_array_equal(target, copies[1])


@pytest.mark.parametrize(
    "change, message",
    [
        ({"R": np.eye(3)}, "R must be a 3-D array"),
        ({"R": np.ones((452, 2, 2))}, r"R must have shape \(452, 3, 3\)"),
        ({"R": np.full((452, 3, 3), np.nan)}, "R contains NaN or inf"),
        ({"handle_positions": np.ones((71, 3))}, r"handle_positions must have shape \(72, 3\)"),
        ({"handle_positions": np.ones((72, 2))}, r"handle_positions must have shape \(72, 3\)"),
        ({"handle_positions": np.full((72, 3), np.inf)}, "handle_positions contains NaN or inf"),
        ({"data": {"V": np.zeros((452, 3))}}, "data must be the result of arap_precompute"),
        ({"data": types.SimpleNamespace(V=np.zeros((452, 3)))}, "data must be the result of arap_precompute"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(mesh_and_handles, change, message):
    V, F, handles = mesh_and_handles("bar_coarse")
    args = {"data": arap_precompute(V, F, handles), "R": np.tile(np.eye(3), (len(V), 1, 1)), "handle_positions": V[handles]}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        arap_global_step(**args)
