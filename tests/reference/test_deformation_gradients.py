import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import deformation_gradients

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_an_affine_map_has_its_linear_part_as_every_gradient(tet_mesh, seed):
    V, T = tet_mesh("hand_tet", seed)
    rng = np.random.default_rng(seed)
    A, t = rng.standard_normal((3, 3)), rng.standard_normal(3)
    J = deformation_gradients(V, V @ A.T + t, T)
    assert J.shape == (len(T), 3, 3)
    np.testing.assert_allclose(J, np.broadcast_to(A, J.shape), atol=1e-9 * np.abs(A).max())


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_the_gradient_maps_every_rest_edge_to_its_deformed_edge(tet_mesh, seed):
    V, T = tet_mesh("bar_tet", seed)
    U = V + 0.3 * np.random.default_rng(seed).standard_normal(V.shape)
    J = deformation_gradients(V, U, T)
    for i, j in [(0, 1), (1, 2), (2, 3), (3, 0)]:
        edge, deformed = V[T[:, j]] - V[T[:, i]], U[T[:, j]] - U[T[:, i]]
        np.testing.assert_allclose(np.einsum("tab,tb->ta", J, edge), deformed, atol=1e-10)


def test_u_must_have_the_shape_of_v(tet_mesh):
    V, T = tet_mesh("bar_tet")
    with pytest.raises(ValueError, match=r"U must have the shape of V, \(1225, 3\), got \(1225, 2\)"):
        deformation_gradients(V, V[:, :2], T)
