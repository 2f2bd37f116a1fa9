import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import deformation_gradients, tet_arap_energy, tet_arap_rotations, tet_volumes

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_rigid_motions_cost_nothing(tet_mesh, random_rotation, seed):
    V, T = tet_mesh("hand_tet", seed)
    R0 = random_rotation(seed)
    U = V @ R0.T + np.random.default_rng(seed).standard_normal(3)
    assert tet_arap_energy(V, U, T, tet_arap_rotations(V, U, T)) <= 1e-20 * len(T)


def test_uniform_scaling_costs_the_volume_times_the_squared_stretch(tet_mesh):
    V, T = tet_mesh("hand_tet", 1)
    R = np.broadcast_to(np.eye(3), (len(T), 3, 3))
    # J = 1.5 I against R = I: ‖0.5 I‖² = 0.75 per unit volume
    assert tet_arap_energy(V, 1.5 * V, T, R) == pytest.approx(0.75 * tet_volumes(V, T).sum(), rel=1e-12)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_energy_is_the_volume_weighted_distance_of_gradients_to_any_matrices(tet_mesh, seed):
    V, T = tet_mesh("bar_tet", seed)
    rng = np.random.default_rng(seed)
    U, R = V + 0.1 * rng.standard_normal(V.shape), rng.standard_normal((len(T), 3, 3))
    expected = sum(v * np.sum((J - Rt) ** 2) for v, J, Rt in zip(tet_volumes(V, T), deformation_gradients(V, U, T), R))
    assert tet_arap_energy(V, U, T, R) == pytest.approx(expected, rel=1e-12)


def test_r_must_have_one_matrix_per_tetrahedron(tet_mesh):
    V, T = tet_mesh("bar_tet")
    with pytest.raises(ValueError, match=r"R must have shape \(5184, 3, 3\), one 3x3 matrix per tetrahedron"):
        tet_arap_energy(V, V, T, np.zeros((len(V), 3, 3)))
