import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_energy
from reference.bounded_biharmonic_weights import bbw, handle_constraints
from reference.fast import fast_energy, fast_global_step, fast_precompute, fast_rotations, fast_solve, rotation_clusters
from reference.linear_blend_skinning import lbs
from starter.meshes import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def turn(V, vertices, angle, shift=0.0):
    """``[Q | t]`` turning ``V[vertices]`` by ``angle`` about their centroid (about the x axis in 3D), then shifting."""
    c, s = np.cos(angle), np.sin(angle)
    d = V.shape[1]
    Q = np.array([[c, -s], [s, c]]) if d == 2 else np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    centre = V[vertices].mean(axis=0)
    return np.c_[Q, centre - Q @ centre + shift]


def posed(skinned_mesh, mesh, angle, shift=0.0):
    """``(V, F, W, fixed, fixed_transforms)``: the first fixed handle at rest, the second turned and shifted."""
    V, F, W, fixed = skinned_mesh(mesh)
    moving = np.flatnonzero(W[:, fixed[1]] == 1.0)
    d = V.shape[1]
    return V, F, W, fixed, np.stack([np.eye(d, d + 1), turn(V, moving, angle, shift)])


def energy_scale(data, T, R):
    """The size of the energy's terms (see ``fast_energy``): its rounding is relative to it."""
    V, F, C = data.V, data.F, data.C
    U = lbs(V, data.W, T)
    R = R[data.clusters]
    return arap_energy(V, U, F, C, np.zeros_like(R)) + arap_energy(V, np.zeros_like(U), F, C, R)


@settings(max_examples=20, deadline=None)
@given(meshes, st.floats(-np.pi, np.pi), st.floats(0.0, 0.5), st.integers(1, 30), seeds)
def test_energies_never_rise_and_the_fixed_transforms_are_met_exactly(skinned_mesh, mesh, angle, shift, k, seed):
    rng = np.random.default_rng(seed)
    V, F, W, fixed, target = posed(skinned_mesh, mesh, angle, shift * rng.normal(size=skinned_mesh(mesh)[0].shape[1]))
    data = fast_precompute(V, F, W, rotation_clusters(W, k, seed), fixed)
    T, energies = fast_solve(data, target, iterations=15)
    assert T.shape == (W.shape[1], V.shape[1], V.shape[1] + 1) and len(energies) == 15
    np.testing.assert_array_equal(T[fixed], target)
    scale = energy_scale(data, T, fast_rotations(data, T))
    assert (np.diff(energies) <= 1e-12 * scale).all()
    assert energies[-1] >= -1e-12 * scale


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_each_energy_is_that_of_the_new_transforms_with_the_rotations_used(skinned_mesh, mesh):
    V, F, W, fixed, target = posed(skinned_mesh, mesh, 1.0)
    d = V.shape[1]
    data = fast_precompute(V, F, W, rotation_clusters(W, 10), fixed)
    start = np.eye(d, d + 1) + 0.1 * np.random.default_rng(0).normal(size=(W.shape[1], d, d + 1))
    T_all, energies = fast_solve(data, target, T0=start, iterations=3)
    T = start.copy()
    T[fixed] = target
    for k in range(3):
        R = fast_rotations(data, T)
        T = fast_global_step(data, R, target)
        assert energies[k] == pytest.approx(fast_energy(data, T, R), rel=1e-12)
        assert energies[k] == pytest.approx(arap_energy(V, lbs(V, W, T), F, data.C, R[data.clusters]), rel=1e-9)
    np.testing.assert_array_equal(T_all, T)


def test_starts_from_the_identity_transforms_with_the_fixed_rows_replaced(skinned_mesh):
    V, F, W, fixed, target = posed(skinned_mesh, "bar_coarse", 1.0)
    data = fast_precompute(V, F, W, rotation_clusters(W, 8), fixed)
    identity = np.tile(np.eye(3, 4), (W.shape[1], 1, 1))
    T_default, E_default = fast_solve(data, target, iterations=4)
    T_identity, E_identity = fast_solve(data, target, T0=identity, iterations=4)
    np.testing.assert_array_equal(T_default, T_identity)
    np.testing.assert_array_equal(E_default, E_identity)
    start = identity + 0.05 * np.random.default_rng(1).normal(size=identity.shape)
    replaced = start.copy()
    replaced[fixed] = target
    np.testing.assert_array_equal(
        fast_solve(data, target, T0=start, iterations=2)[0], fast_solve(data, target, T0=replaced, iterations=2)[0]
    )


def test_two_iterations_are_one_iteration_twice(skinned_mesh):
    V, F, W, fixed, target = posed(skinned_mesh, "character", 2.0)
    data = fast_precompute(V, F, W, rotation_clusters(W, 8), fixed)
    T1, E1 = fast_solve(data, target, iterations=1)
    T2, E2 = fast_solve(data, target, T0=T1, iterations=1)
    T, E = fast_solve(data, target, iterations=2)
    np.testing.assert_array_equal(T, T2)
    np.testing.assert_array_equal(E, np.r_[E1, E2])


def test_zero_iterations_return_the_start(skinned_mesh):
    V, F, W, fixed, target = posed(skinned_mesh, "bar_coarse", 1.0)
    T, energies = fast_solve(fast_precompute(V, F, W, rotation_clusters(W, 4), fixed), target, iterations=0)
    expected = np.tile(np.eye(3, 4), (W.shape[1], 1, 1))
    expected[fixed] = target
    np.testing.assert_array_equal(T, expected)
    assert len(energies) == 0


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_a_rigid_motion_of_the_rest_pose_is_a_fixed_point_at_zero_energy(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    data = fast_precompute(V, F, W, rotation_clusters(W, 6), fixed)
    rigid = np.c_[special_ortho_group.rvs(d, random_state=np.random.default_rng(2)), np.ones(d)]
    start = np.tile(rigid, (W.shape[1], 1, 1))
    T, energies = fast_solve(data, start[fixed], T0=start, iterations=5)
    # optimal_rotation's 3D rotations are exact to ~1e-10 (their tr(R S) to ~1e-15)
    np.testing.assert_allclose(T, start, rtol=0, atol=1e-9)
    assert np.abs(energies).max() <= 1e-12 * energy_scale(data, T, fast_rotations(data, T))


def test_inputs_are_not_modified(skinned_mesh):
    V, F, W, fixed, target = posed(skinned_mesh, "bar_coarse", 1.0)
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), fixed)
    start = np.tile(np.eye(3, 4), (W.shape[1], 1, 1)) + 0.01
    copies = (target.copy(), start.copy(), data.W.copy())
    fast_solve(data, target, T0=start, iterations=2)
    for a, b in zip((target, start, data.W), copies):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"fixed_transforms": np.ones((1, 3, 4))}, r"fixed_transforms must have shape \(2, 3, 4\)"),
        ({"fixed_transforms": np.full((2, 3, 4), np.nan)}, "fixed_transforms contains NaN or inf"),
        ({"T0": np.ones((5, 2, 3))}, r"T0 must have shape \(5, 3, 4\), one affine transform per handle"),
        ({"T0": np.ones((5, 12))}, "T0 must be a 3-D array"),
        ({"T0": np.full((5, 3, 4), np.inf)}, "T0 contains NaN or inf"),
        ({"iterations": -1}, "iterations must be a non-negative integer"),
        ({"iterations": 2.5}, "iterations must be a non-negative integer"),
        ({"iterations": True}, "iterations must be a non-negative integer"),
        ({"iterations": "3"}, "iterations must be a non-negative integer"),
        ({"data": None}, "data must be the result of fast_precompute"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(skinned_mesh, change, message):
    V, F, W, fixed, target = posed(skinned_mesh, "bar_coarse", 1.0)
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), fixed)
    args = {"data": data, "fixed_transforms": target, "T0": None, "iterations": 2}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        fast_solve(**args)


def test_on_the_volumetric_bar_the_energy_never_increases_and_a_twist_stays_a_twist():
    V, T = load_mesh("bar_tet")
    sets = load_handles("bar_tet")
    rings = [np.flatnonzero(V[:, 0] == x) for x in (1.0, 2.0, 3.0)]
    W = bbw(V, T, *handle_constraints([sets["left"], sets["right"], *rings]))
    data = fast_precompute(V, T, W, rotation_clusters(W, 20), [0, 1])
    c, s = np.cos(np.pi / 2), np.sin(np.pi / 2)
    turn = np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])
    centre = np.array([4.0, 0.5, 0.5])
    fixed = np.stack([np.eye(3, 4), np.c_[turn, centre - turn @ centre]])
    transforms, energies = fast_solve(data, fixed, iterations=30)
    assert (np.diff(energies) <= 1e-10 * energies[0]).all()
    U = lbs(V, W, transforms)
    # the middle cross-section turns by about half the end's angle and keeps its size
    middle = rings[1]
    spread = np.linalg.norm(U[middle, 1:] - U[middle, 1:].mean(axis=0), axis=1)
    assert spread.max() == pytest.approx(np.sqrt(0.5), rel=0.05)
