import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import tet_arap_energy, tet_arap_precompute, tet_arap_rotations, tet_arap_solve, tet_volumes
from starter.meshes import load_handles

seeds = st.integers(0, 2**32 - 1)


def twisted_bar(V, angle):
    """End faces of bar_tet: the left at rest, the right turned by ``angle`` about the bar's axis."""
    sets = load_handles("bar_tet")
    handles = np.concatenate([sets["left"], sets["right"]])
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])
    centre = np.array([4.0, 0.5, 0.5])
    targets = np.vstack([V[sets["left"]], (V[sets["right"]] - centre) @ turn.T + centre])
    return handles, targets


def test_twist_matches_igl_arap_with_tetrahedral_elements(tet_mesh):
    V, T = tet_mesh("bar_tet")
    handles, targets = twisted_bar(V, np.pi / 2)
    U, energies = tet_arap_solve(tet_arap_precompute(V, T, handles), targets, iterations=50)
    data = igl.ARAPData()
    data.energy = igl.ARAP_ENERGY_TYPE_ELEMENTS
    data.max_iter = 50
    igl.arap_precomputation(V, T, 3, handles, data)
    # libigl fits its rotations in single precision
    np.testing.assert_allclose(U, igl.arap_solve(targets, data, V.copy()), atol=1e-5)
    # fresh rotations can only lower the energy of the last global step's rotations
    assert tet_arap_energy(V, U, T, tet_arap_rotations(V, U, T)) <= energies[-1]


@settings(max_examples=8, deadline=None)
@given(seed=seeds, angle=st.floats(-3.0, 3.0))
def test_energy_never_increases_and_handles_land_exactly(tet_mesh, seed, angle):
    V, T = tet_mesh("bar_tet", seed)
    handles, targets = twisted_bar(V, angle)
    U, energies = tet_arap_solve(tet_arap_precompute(V, T, handles), targets, iterations=15)
    assert (np.diff(energies) <= 1e-12 * energies[0] + 1e-24).all()
    assert np.array_equal(U[handles], targets)


@settings(max_examples=8, deadline=None)
@given(seed=seeds)
def test_a_rigid_motion_of_the_whole_solid_is_a_fixed_point_of_zero_energy(tet_mesh, random_rotation, seed):
    V, T = tet_mesh("hand_tet", seed)
    R0, t = random_rotation(seed), np.random.default_rng(seed).standard_normal(3)
    handles = np.concatenate(load_handles("hand_tet")["bones"][:2])
    moved = V @ R0.T + t
    U, energies = tet_arap_solve(tet_arap_precompute(V, T, handles), moved[handles], U0=moved, iterations=3)
    np.testing.assert_allclose(U, moved, atol=1e-9)
    assert energies.max() <= 1e-18


def test_a_quarter_twist_keeps_the_volume_within_two_percent_and_inverts_nothing(tet_mesh):
    V, T = tet_mesh("bar_tet")
    handles, targets = twisted_bar(V, np.pi / 2)
    U, _ = tet_arap_solve(tet_arap_precompute(V, T, handles), targets, iterations=100)
    assert tet_volumes(U, T).sum() == pytest.approx(4.0, rel=0.02)
    assert tet_volumes(U, T).min() > 0


def test_zero_iterations_returns_the_start_with_the_handles_placed(tet_mesh):
    V, T = tet_mesh("bar_tet")
    handles, targets = twisted_bar(V, 1.0)
    U, energies = tet_arap_solve(tet_arap_precompute(V, T, handles), targets, iterations=0)
    assert energies.shape == (0,)
    expected = V.copy()
    expected[handles] = targets
    assert np.array_equal(U, expected)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(iterations=-1), "iterations must be a non-negative integer"),
        (dict(iterations=2.0), "iterations must be a non-negative integer"),
        (dict(U0=np.zeros((3, 3))), r"U0 must have the shape of V, \(1225, 3\)"),
    ],
)
def test_bad_arguments_are_named(tet_mesh, kwargs, message):
    V, T = tet_mesh("bar_tet")
    handles, targets = twisted_bar(V, 1.0)
    with pytest.raises(ValueError, match=message):
        tet_arap_solve(tet_arap_precompute(V, T, handles), targets, **kwargs)
    with pytest.raises(ValueError, match=r"data must be the result of tet_arap_precompute"):
        tet_arap_solve(object(), targets)
