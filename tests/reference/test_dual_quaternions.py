import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from reference.dual_quaternion_skinning import dual_quaternions

seeds = st.integers(0, 2**32 - 1)


def rigid_transforms(rng, m):
    R = Rotation.random(m, random_state=rng).as_matrix()
    return np.concatenate([R, rng.normal(0.0, 3.0, (m, 3, 1))], axis=2)


def quaternion_product(p, q):
    """Hamilton product of ``(w, x, y, z)`` quaternions, row by row."""
    w1, v1, w2, v2 = p[:, 0], p[:, 1:], q[:, 0], q[:, 1:]
    return np.c_[w1 * w2 - np.einsum("ij,ij->i", v1, v2), w1[:, None] * v2 + w2[:, None] * v1 + np.cross(v1, v2)]


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 8), seeds)
def test_real_part_is_the_rotations_unit_quaternion_with_non_negative_w(m, seed):
    T = rigid_transforms(np.random.default_rng(seed), m)
    Q = dual_quaternions(T)
    assert Q.shape == (m, 2, 4) and Q.dtype == np.float64
    scipy_q = Rotation.from_matrix(T[:, :, :3]).as_quat()[:, [3, 0, 1, 2]]  # scipy stores (x, y, z, w)
    scipy_q *= np.sign(scipy_q[:, :1] + (scipy_q[:, :1] == 0))
    np.testing.assert_allclose(Q[:, 0], scipy_q, rtol=0, atol=1e-12)
    assert np.all(Q[:, 0, 0] >= 0)


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 8), seeds)
def test_dual_part_is_half_the_translation_times_the_real_part_and_orthogonal_to_it(m, seed):
    T = rigid_transforms(np.random.default_rng(seed), m)
    Q = dual_quaternions(T)
    t_quaternion = np.c_[np.zeros(m), T[:, :, 3]]
    np.testing.assert_allclose(Q[:, 1], 0.5 * quaternion_product(t_quaternion, Q[:, 0]), rtol=0, atol=1e-12)
    # a unit dual quaternion: ‖q_0‖ = 1 and q_0 · q_e = 0
    np.testing.assert_allclose(np.linalg.norm(Q[:, 0], axis=1), 1.0, rtol=0, atol=1e-14)
    np.testing.assert_allclose(np.einsum("ij,ij->i", Q[:, 0], Q[:, 1]), 0.0, rtol=0, atol=1e-12)


@pytest.mark.parametrize("axis", np.eye(3))
def test_half_turns_where_w_vanishes_give_the_axis_as_quaternion(axis):
    # tr R = -1: Shepperd's method must take the axis component, not divide by w = 0
    R = 2.0 * np.outer(axis, axis) - np.eye(3)
    Q = dual_quaternions(np.c_[R, np.zeros(3)][None])
    assert np.allclose(np.abs(Q[0, 0]), np.r_[0.0, axis], atol=1e-15)
    np.testing.assert_array_equal(Q[0, 1], 0.0)


def test_inputs_are_not_modified():
    T = rigid_transforms(np.random.default_rng(3), 4)
    before = T.copy()
    dual_quaternions(T)
    np.testing.assert_array_equal(T, before)


T_OK = np.tile(np.eye(3, 4), (2, 1, 1))


@pytest.mark.parametrize(
    "T, message",
    [
        (T_OK[0], "T must be a 3-D array"),
        (np.tile(np.eye(2, 3), (2, 1, 1)), r"T must have shape \(m, 3, 4\).* got \(2, 2, 3\)"),
        (T_OK * [[2.0], [1.0], [1.0]], r"T\[0\] is not rigid"),
        (T_OK * [[1.0], [1.0], [-1.0]], r"T\[0\] is not rigid: .* det R = \+1"),
        (np.where(T_OK == 1, np.inf, T_OK), "T contains NaN or inf"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(T, message):
    with pytest.raises(ValueError, match=message):
        dual_quaternions(T)
