import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.fast import fast_energy, fast_global_step, fast_precompute, fast_rotations, rotation_clusters
from reference.linear_blend_skinning import lbs

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def random_transforms(rng, m, d, size):
    return np.eye(d, d + 1) + size * rng.normal(size=(m, d, d + 1))


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 30), seeds)
def test_the_result_minimizes_the_energy_for_the_given_rotations(skinned_mesh, mesh, k, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    data = fast_precompute(V, F, W, rotation_clusters(W, k, seed), fixed)
    R = fast_rotations(data, random_transforms(rng, W.shape[1], d, 0.3))
    target = random_transforms(rng, len(fixed), d, 0.3)
    T = fast_global_step(data, R, target)
    assert T.shape == (W.shape[1], d, d + 1) and T.dtype == np.float64
    np.testing.assert_array_equal(T[fixed], target)
    E = fast_energy(data, T, R)
    for scale in (1e-3, 1e-1):
        D = scale * rng.normal(size=T.shape)
        D[fixed] = 0.0
        plus, minus = fast_energy(data, T + D, R), fast_energy(data, T - D, R)
        # E is quadratic in T: E(T ± D) = E(T) ± ∇E·D + DᵀHD, so a zero gradient on the
        # free transforms makes both sides equal, and both rise above E(T)
        curvature = plus + minus - 2.0 * E
        assert curvature > 0
        assert abs(plus - minus) <= 1e-6 * curvature


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 12), seeds)
def test_rigidly_moved_fixed_handles_and_rotations_move_every_handle_the_same_way(skinned_mesh, mesh, k, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    Q, t = special_ortho_group.rvs(d, random_state=rng), rng.normal(size=d)
    data = fast_precompute(V, F, W, rotation_clusters(W, k, seed), fixed)
    T = fast_global_step(data, np.tile(Q, (k, 1, 1)), np.tile(np.c_[Q, t], (len(fixed), 1, 1)))
    np.testing.assert_allclose(T, np.broadcast_to(np.c_[Q, t], T.shape), rtol=0, atol=1e-10)


def test_with_every_handle_fixed_the_fixed_transforms_are_the_answer(skinned_mesh):
    V, F, W, _ = skinned_mesh("bar_coarse")
    order = np.random.default_rng(0).permutation(W.shape[1])
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), order)
    target = random_transforms(np.random.default_rng(1), len(order), 3, 0.5)
    T = fast_global_step(data, np.tile(np.eye(3), (4, 1, 1)), target)
    np.testing.assert_array_equal(T[order], target)


def test_moving_the_rest_mesh_far_from_the_origin_moves_the_result_with_it(skinned_mesh):
    # the unknowns' [v; 1] columns are nearly parallel 1e4 away from the origin
    V, F, W, fixed = skinned_mesh("bar_coarse")
    shift = np.array([1e4, -2e4, 5e3])
    clusters = rotation_clusters(W, 6)
    rng = np.random.default_rng(5)
    R = special_ortho_group.rvs(3, size=6, random_state=rng)
    target = random_transforms(rng, len(fixed), 3, 0.3)
    # u = A v + t = A (v + s) + (t - A s)  and the result moved by s
    moved = target.copy()
    moved[:, :, 3] += shift - target[:, :, :3] @ shift
    near = lbs(V, W, fast_global_step(fast_precompute(V, F, W, clusters, fixed), R, target))
    far = lbs(V + shift, W, fast_global_step(fast_precompute(V + shift, F, W, clusters, fixed), R, moved))
    np.testing.assert_allclose(far - shift, near, rtol=0, atol=1e-9)


def test_inputs_are_not_modified(skinned_mesh):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), fixed)
    R = np.tile(np.eye(3), (4, 1, 1))
    target = np.tile(np.eye(3, 4), (2, 1, 1)) + 0.1
    copies = (R.copy(), target.copy())
    fast_global_step(data, R, target)
    np.testing.assert_array_equal(R, copies[0])
    np.testing.assert_array_equal(target, copies[1])


@pytest.mark.parametrize(
    "change, message",
    [
        ({"R": np.eye(3)}, "R must be a 3-D array"),
        ({"R": np.ones((5, 3, 3))}, r"R must have shape \(4, 3, 3\), one rotation per cluster"),
        ({"R": np.ones((4, 2, 2))}, r"R must have shape \(4, 3, 3\)"),
        ({"R": np.full((4, 3, 3), np.nan)}, "R contains NaN or inf"),
        (
            {"fixed_transforms": np.ones((3, 3, 4))},
            r"fixed_transforms must have shape \(2, 3, 4\), one affine transform per fixed handle",
        ),
        ({"fixed_transforms": np.ones((2, 3, 3))}, r"fixed_transforms must have shape \(2, 3, 4\)"),
        ({"fixed_transforms": np.ones((2, 12))}, "fixed_transforms must be a 3-D array"),
        ({"fixed_transforms": np.full((2, 3, 4), np.inf)}, "fixed_transforms contains NaN or inf"),
        ({"data": None}, "data must be the result of fast_precompute"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(skinned_mesh, change, message):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    args = {
        "data": fast_precompute(V, F, W, rotation_clusters(W, 4), fixed),
        "R": np.tile(np.eye(3), (4, 1, 1)),
        "fixed_transforms": np.tile(np.eye(3, 4), (2, 1, 1)),
    }
    args.update(change)
    with pytest.raises(ValueError, match=message):
        fast_global_step(**args)
