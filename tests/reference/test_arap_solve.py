import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_energy, arap_global_step, arap_precompute, arap_rotations, arap_solve
from starter.meshes import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)


def bar(mesh="bar_coarse"):
    V, F = load_mesh(mesh)
    ends = load_handles(mesh)
    return V, F, ends["left"], ends["right"]


def twisted(V, left, right, angle):
    """Handle positions: the left end at rest, the right end turned by ``angle`` about the bar's axis."""
    c = V[right].mean(axis=0)
    turn = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(angle), -np.sin(angle)], [0.0, np.sin(angle), np.cos(angle)]])
    return np.vstack([V[left], (V[right] - c) @ turn.T + c])


def character():
    """The 2D character (triangulated by Triangle) with its head and feet regions as handles."""
    V, F = load_mesh("character")
    head, *feet = load_handles("character")["regions"]
    handles = np.concatenate([head, *feet])
    target = V[handles].copy()
    target[: len(head)] += [0.3, 0.1]
    c = V[feet[0]].mean(axis=0)
    a = 0.5
    turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    target[len(head) : len(head) + len(feet[0])] = (V[feet[0]] - c) @ turn.T + c
    return V, F, handles, target


def igl_arap(V, F, handles, target, iterations):
    data = igl.ARAPData()
    data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
    data.max_iter = iterations
    igl.arap_precomputation(V, F, V.shape[1], handles.astype(np.int32), data)
    start = V.copy()
    start[handles] = target
    return igl.arap_solve(target, data, start)


@pytest.mark.parametrize(
    "degrees, tolerance",
    # libigl fits 3D rotations in single precision: the gap grows with the deformation
    [(20, 1e-6), (90, 1e-3)],
)
def test_matches_igl_spokes_and_rims_on_a_twisted_bar(degrees, tolerance):
    V, F, left, right = bar("bar")
    handles = np.concatenate([left, right])
    target = twisted(V, left, right, np.radians(degrees))
    U, _ = arap_solve(arap_precompute(V, F, handles), target, iterations=30)
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    assert np.abs(U - igl_arap(V, F, handles, target, 30)).max() < tolerance * diagonal


def test_matches_igl_spokes_and_rims_in_2d():
    V, F, handles, target = character()
    U, _ = arap_solve(arap_precompute(V, F, handles), target, iterations=30)
    diagonal = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    assert np.abs(U - igl_arap(V, F, handles, target, 30)).max() < 1e-10 * diagonal


def energy_scale(data, U):
    """``3 Σ C (‖e‖² + ‖e'‖²)``, the size of the energy's terms: its rounding is relative to it."""
    return 3.0 * (data.rest_dirichlet - np.sum(U * (data.L @ U)))


@settings(max_examples=25, deadline=None)
@given(st.floats(-np.pi, np.pi), st.floats(0.0, 1.0), st.floats(0.0, 0.05), seeds)
def test_energies_never_rise_and_the_handles_are_met_exactly(angle, shift, jitter, seed):
    V, F, left, right = bar()
    handles = np.concatenate([left, right])
    rng = np.random.default_rng(seed)
    target = twisted(V, left, right, angle)
    target[len(left) :] += shift * rng.normal(size=3)
    target += jitter * rng.normal(size=target.shape)
    data = arap_precompute(V, F, handles)
    U, energies = arap_solve(data, target, iterations=30)
    assert len(energies) == 30
    np.testing.assert_array_equal(U[handles], target)
    assert (np.diff(energies) <= 1e-11 * energies[0] + 1e-12 * energy_scale(data, U)).all()
    assert energies[-1] >= -1e-12 * energy_scale(data, U)


@pytest.mark.parametrize("dim", [2, 3])
def test_each_energy_is_that_of_the_new_positions_with_the_rotations_used(dim):
    if dim == 3:
        V, F, left, right = bar()
        handles = np.concatenate([left, right])
        target = twisted(V, left, right, 1.0)
    else:
        V, F, handles, target = character()
    data = arap_precompute(V, F, handles)
    start = V + 0.05 * np.random.default_rng(0).normal(size=V.shape)
    U_all, energies = arap_solve(data, target, U0=start, iterations=3)
    U = start.copy()
    U[handles] = target
    for k in range(3):
        R = arap_rotations(V, U, F, data.C)
        U = arap_global_step(data, R, target)
        assert energies[k] == pytest.approx(arap_energy(V, U, F, data.C, R), rel=1e-10)
    np.testing.assert_allclose(U_all, U, rtol=0, atol=1e-12)


def test_starts_from_the_rest_pose_with_the_handle_rows_replaced():
    V, F, left, right = bar()
    handles = np.concatenate([left, right])
    data = arap_precompute(V, F, handles)
    target = twisted(V, left, right, 1.0)
    U_default, E_default = arap_solve(data, target, iterations=4)
    U_rest, E_rest = arap_solve(data, target, U0=V, iterations=4)
    np.testing.assert_array_equal(U_default, U_rest)
    np.testing.assert_array_equal(E_default, E_rest)
    start = V + 0.05 * np.random.default_rng(1).normal(size=V.shape)
    fixed = start.copy()
    fixed[handles] = target
    np.testing.assert_array_equal(arap_solve(data, target, U0=start, iterations=2)[0], arap_solve(data, target, U0=fixed, iterations=2)[0])


def test_two_iterations_are_one_iteration_twice():
    V, F, left, right = bar()
    data = arap_precompute(V, F, np.concatenate([left, right]))
    target = twisted(V, left, right, 2.0)
    U1, E1 = arap_solve(data, target, iterations=1)
    U2, E2 = arap_solve(data, target, U0=U1, iterations=1)
    U, E = arap_solve(data, target, iterations=2)
    np.testing.assert_allclose(U, U2, rtol=0, atol=1e-13)
    np.testing.assert_allclose(E, np.r_[E1, E2], rtol=1e-12)


def test_zero_iterations_return_the_start():
    V, F, left, right = bar()
    handles = np.concatenate([left, right])
    target = twisted(V, left, right, 1.0)
    U, energies = arap_solve(arap_precompute(V, F, handles), target, iterations=0)
    expected = V.copy()
    expected[handles] = target
    np.testing.assert_array_equal(U, expected)
    assert len(energies) == 0


def test_a_rigid_motion_of_the_rest_pose_is_a_fixed_point_at_zero_energy():
    V, F, left, right = bar()
    handles = np.concatenate([left, right])
    data = arap_precompute(V, F, handles)
    Q = special_ortho_group.rvs(3, random_state=np.random.default_rng(2))
    rigid = V @ Q.T + 1.0
    U, energies = arap_solve(data, rigid[handles], U0=rigid, iterations=5)
    np.testing.assert_allclose(U, rigid, rtol=0, atol=1e-12)
    assert np.abs(energies).max() < 1e-12 * energy_scale(data, U)


def test_inputs_are_not_modified():
    V, F, left, right = bar()
    data = arap_precompute(V, F, np.concatenate([left, right]))
    target = twisted(V, left, right, 1.0)
    start = V + 0.01
    copies = (target.copy(), start.copy(), data.V.copy())
    arap_solve(data, target, U0=start, iterations=2)
    for a, b in zip((target, start, data.V), copies):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"handle_positions": np.ones((71, 3))}, r"handle_positions must have shape \(72, 3\)"),
        ({"handle_positions": np.full((72, 3), np.nan)}, "handle_positions contains NaN or inf"),
        ({"U0": np.ones((452, 2))}, r"U0 must have the shape of V, \(452, 3\)"),
        ({"U0": np.ones(452)}, "U0 must be a 2-D array"),
        ({"U0": np.full((452, 3), np.inf)}, "U0 contains NaN or inf"),
        ({"iterations": -1}, "iterations must be a non-negative integer"),
        ({"iterations": 2.5}, "iterations must be a non-negative integer"),
        ({"iterations": True}, "iterations must be a non-negative integer"),
        ({"iterations": "3"}, "iterations must be a non-negative integer"),
        ({"data": None}, "data must be the result of arap_precompute"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(change, message):
    V, F, left, right = bar()
    handles = np.concatenate([left, right])
    args = {"data": arap_precompute(V, F, handles), "handle_positions": V[handles], "U0": None, "iterations": 2}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        arap_solve(**args)


@settings(max_examples=15, deadline=None)
@given(st.sampled_from(["bar_coarse", "character"]), seeds, st.floats(0.0, 1.0))
def test_cells_inside_handle_regions_give_the_plain_local_global_iterates(mesh, seed, radius):
    # arap_solve fits the rotations of cells whose triangles hold only handles once per solve
    V, F = load_mesh(mesh)
    rng = np.random.default_rng(seed)
    centre = V[rng.integers(len(V))]
    region = np.flatnonzero(np.linalg.norm(V - centre, axis=1) <= radius * np.ptp(V, axis=0).max())
    handles = np.union1d(region, rng.choice(len(V), 2, replace=False))
    data = arap_precompute(V, F, handles)
    target = V[handles] + 0.1 * rng.normal(size=(len(handles), V.shape[1]))
    U_all, energies = arap_solve(data, target, iterations=3)
    U = V.copy()
    U[handles] = target
    for k in range(3):
        R = arap_rotations(V, U, F, data.C)
        U = arap_global_step(data, R, target)
        assert energies[k] == pytest.approx(arap_energy(V, U, F, data.C, R), rel=1e-10, abs=1e-12)
    np.testing.assert_allclose(U_all, U, rtol=0, atol=1e-11)
