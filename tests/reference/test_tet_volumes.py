import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import tet_volumes

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=20, deadline=None)
@given(seed=seeds)
def test_signed_volumes_equal_igl_and_sum_to_the_enclosed_volume(tet_mesh, seed):
    V, T = tet_mesh("hand_tet", seed)
    vol = tet_volumes(V, T)
    np.testing.assert_allclose(vol, igl.volume(V, T), rtol=1e-12, atol=1e-18)
    assert vol.min() > 0
    # the boundary (faces of one tet, oriented outward) encloses the same volume: divergence theorem
    faces = np.concatenate([T[:, [1, 2, 3]], T[:, [0, 3, 2]], T[:, [0, 1, 3]], T[:, [0, 2, 1]]])
    _, which, count = np.unique(np.sort(faces, axis=1), axis=0, return_inverse=True, return_counts=True)
    B = faces[count[which.ravel()] == 1]
    enclosed = np.einsum("ij,ij->i", V[B[:, 0]], np.cross(V[B[:, 1]], V[B[:, 2]])).sum() / 6
    assert vol.sum() == pytest.approx(enclosed, rel=1e-12)


def test_swapping_two_corners_flips_the_sign_and_a_unit_corner_has_one_sixth():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    assert tet_volumes(V, [[0, 1, 2, 3], [0, 2, 1, 3]]).tolist() == [1 / 6, -1 / 6]


@pytest.mark.parametrize(
    "V, T, message",
    [
        (np.eye(4)[:, :2], [[0, 1, 2, 3]], r"V must have shape \(n, 3\) for a tetrahedral mesh"),
        (np.eye(3), [[0, 1, 2]], r"T must have shape \(f, 4\)"),
        (np.eye(3), [[0, 1, 2, 3]], r"T has a vertex index out of range: T\[0, 3\] = 3"),
        (np.eye(4)[:, :3], [[0, 1, 1, 3]], r"T has a tetrahedron with a repeated vertex"),
        (np.eye(4)[:, :3], [[0.0, 1, 2, 3]], "T must be an integer array"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, T, message):
    with pytest.raises(ValueError, match=message):
        tet_volumes(V, T)
