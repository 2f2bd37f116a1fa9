import numpy as np
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import deformation_gradients, tet_arap_rotations

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_a_rigid_motion_gives_its_rotation_in_every_tetrahedron(tet_mesh, random_rotation, seed):
    V, T = tet_mesh("hand_tet", seed)
    R0 = random_rotation(seed)
    R = tet_arap_rotations(V, V @ R0.T + np.random.default_rng(seed).standard_normal(3), T)
    np.testing.assert_allclose(R, np.broadcast_to(R0, R.shape), atol=1e-10)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_rotations_are_proper_and_nearest_to_the_gradient_even_when_tets_invert(tet_mesh, random_rotation, seed):
    V, T = tet_mesh("bar_tet", seed)
    U = V + 0.2 * np.random.default_rng(seed).standard_normal(V.shape)
    J = deformation_gradients(V, U, T)
    R = tet_arap_rotations(V, U, T)
    assert (np.linalg.det(J) < 0).any(), "the test should see inverted tetrahedra"
    np.testing.assert_allclose(R @ R.transpose(0, 2, 1), np.broadcast_to(np.eye(3), R.shape), atol=1e-12)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)
    # no rotation is nearer: compare with the SVD's sign-corrected answer and with random rotations
    Uj, s, Vt = np.linalg.svd(J)
    D = np.ones((len(J), 3))
    D[:, 2] = np.sign(np.linalg.det(Uj @ Vt))
    np.testing.assert_allclose(R, Uj @ (D[:, :, None] * Vt), atol=1e-8)
    other = random_rotation(seed + 1)
    assert (np.sum((J - R) ** 2, axis=(1, 2)) <= np.sum((J - other) ** 2, axis=(1, 2)) + 1e-12).all()
