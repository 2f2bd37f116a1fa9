import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.transform import Rotation

from reference.dual_quaternion_skinning import dual_quaternion_transforms, dual_quaternions

seeds = st.integers(0, 2**32 - 1)


def rigid_transforms(rng, m):
    R = Rotation.random(m, random_state=rng).as_matrix()
    return np.concatenate([R, rng.normal(0.0, 3.0, (m, 3, 1))], axis=2)


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 8), st.floats(-5.0, 5.0).filter(lambda s: abs(s) > 1e-3), seeds)
def test_a_scaled_dual_quaternion_gives_back_its_rigid_transform(m, scale, seed):
    # the round trip, for q̂ and any non-zero multiple of it (the sign of q̂ is irrelevant)
    T = rigid_transforms(np.random.default_rng(seed), m)
    back = dual_quaternion_transforms(scale * dual_quaternions(T))
    assert back.shape == (m, 3, 4) and back.dtype == np.float64
    np.testing.assert_allclose(back, T, rtol=0, atol=1e-12 * max(1.0, np.abs(T).max()))


@settings(max_examples=30, deadline=None)
@given(seeds)
def test_any_non_zero_real_part_gives_a_rotation(seed):
    rng = np.random.default_rng(seed)
    Q = rng.normal(size=(6, 2, 4))
    T = dual_quaternion_transforms(Q)
    R = T[:, :, :3]
    np.testing.assert_allclose(np.einsum("kji,kjl->kil", R, R), np.tile(np.eye(3), (6, 1, 1)), atol=1e-13)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-13)


def test_translation_ignores_the_dual_part_along_the_real_part():
    # a blended q̂ has q_0 · q_e != 0; t = 2 vec(c_e c̄_0) drops that component (Kavan et al. 2008, algorithm 1)
    Q = dual_quaternions(rigid_transforms(np.random.default_rng(1), 1))
    shifted = Q.copy()
    shifted[0, 1] += 0.7 * Q[0, 0]
    np.testing.assert_allclose(dual_quaternion_transforms(shifted), dual_quaternion_transforms(Q), atol=1e-13)


@pytest.mark.parametrize(
    "Q, message",
    [
        (np.zeros((2, 8)), "Q must be a 3-D array"),
        (np.ones((2, 4, 2)), r"Q must have shape \(k, 2, 4\).* got \(2, 4, 2\)"),
        (np.array([np.ones((2, 4)), [[0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0, 1.0]]]), r"Q\[1, 0\] \(the real part\) is zero"),
        (np.full((1, 2, 4), np.nan), "Q contains NaN or inf"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(Q, message):
    with pytest.raises(ValueError, match=message):
        dual_quaternion_transforms(Q)
