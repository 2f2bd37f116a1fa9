import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import TET_EDGES, tet_cotangent_weights

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=20, deadline=None)
@given(seed=seeds, name=st.sampled_from(["bar_tet", "hand_tet"]))
def test_weights_equal_igl_cotmatrix_entries(tet_mesh, seed, name):
    V, T = tet_mesh(name, seed)
    C = tet_cotangent_weights(V, T)
    assert C.shape == (len(T), 6)
    np.testing.assert_allclose(C, igl.cotmatrix_entries(V, T), rtol=1e-9, atol=1e-12 * np.abs(C).max())


def test_weights_are_the_opposite_edge_length_times_the_dihedral_cotangent_over_six():
    rng = np.random.default_rng(3)
    V = rng.standard_normal((4, 3))
    T = np.array([[0, 1, 2, 3]])
    if np.linalg.det(V[1:] - V[0]) < 0:
        T = T[:, [0, 2, 1, 3]]
    C = tet_cotangent_weights(V, T)[0]
    for e, (i, j) in enumerate(TET_EDGES):
        k, l = sorted(set(range(4)) - {i, j})
        a, b = V[T[0, k]], V[T[0, l]]
        axis = (b - a) / np.linalg.norm(b - a)
        # dihedral angle at edge kl: between the faces (k, l, i) and (k, l, j)
        ui, uj = V[T[0, i]] - a, V[T[0, j]] - a
        ui, uj = ui - (ui @ axis) * axis, uj - (uj @ axis) * axis
        cos = ui @ uj / np.linalg.norm(ui) / np.linalg.norm(uj)
        assert C[e] == pytest.approx(np.linalg.norm(b - a) * cos / np.sqrt(1 - cos**2) / 6, rel=1e-10)


def test_orientation_does_not_matter():
    V, T = np.eye(4)[:, :3] + 0.1, np.array([[3, 0, 1, 2]])
    np.testing.assert_allclose(tet_cotangent_weights(V, T), tet_cotangent_weights(V, T[:, [1, 0, 2, 3]])[:, [1, 0, 2, 4, 3, 5]])


def test_a_flat_tetrahedron_is_named():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1]])
    with pytest.raises(ValueError, match=r"T has a flat tetrahedron .*T\[1\] = \[0, 1, 2, 3\]"):
        tet_cotangent_weights(V, [[0, 1, 2, 4], [0, 1, 2, 3]])
