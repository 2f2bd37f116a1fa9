import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial.distance import pdist
from scipy.spatial.transform import Rotation

from reference.dual_quaternion_skinning import dqs
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "cylinder"])


def rigid_transforms(rng, m):
    R = Rotation.random(m, random_state=rng).as_matrix()
    return np.concatenate([R, rng.normal(0.0, 3.0, (m, 3, 1))], axis=2)


def random_weights(rng, n, m):
    W = rng.uniform(size=(n, m)) ** 3
    return W / W.sum(axis=1, keepdims=True)


def libigl_dqs(V, W, T):
    """libigl's ``igl::dqs`` (include/igl/dqs.cpp), transcribed loop for loop.

    The python bindings of libigl 2.6.3 do not expose ``dqs``, so this transcription
    of its C++ is the oracle; quaternions come from scipy, not from the reference.
    """
    vQ = Rotation.from_matrix(T[:, :, :3]).as_quat()  # (x, y, z, w), as Eigen's coeffs()
    vT = T[:, :, 3]
    vD = np.empty_like(vQ)
    for c, ((x, y, z, w), t) in enumerate(zip(vQ, vT)):
        vD[c] = [
            0.5 * (t[0] * w + t[1] * z - t[2] * y),
            0.5 * (-t[0] * z + t[1] * w + t[2] * x),
            0.5 * (t[0] * y - t[1] * x + t[2] * w),
            -0.5 * (t[0] * x + t[1] * y + t[2] * z),
        ]
    U = np.empty_like(V)
    for i, v in enumerate(V):
        b0, be = W[i, 0] * vQ[0], W[i, 0] * vD[0]
        for c in range(1, W.shape[1]):
            sign = -1.0 if vQ[0] @ vQ[c] < 0 else 1.0
            b0, be = b0 + sign * W[i, c] * vQ[c], be + sign * W[i, c] * vD[c]
        c0, ce = b0 / np.linalg.norm(b0), be / np.linalg.norm(b0)
        d0, de, a0, ae = c0[:3], ce[:3], c0[3], ce[3]
        U[i] = v + 2 * np.cross(d0, np.cross(d0, v) + a0 * v) + 2 * (a0 * de - ae * d0 + np.cross(d0, de))
    return U


def turn_about_x(degrees):
    return np.c_[Rotation.from_euler("x", degrees, degrees=True).as_matrix(), np.zeros(3)]


@settings(max_examples=15, deadline=None)
@given(meshes, st.integers(1, 6), seeds)
def test_equals_libigls_dqs_for_random_weights_and_rigid_transforms(mesh, m, seed):
    rng = np.random.default_rng(seed)
    V = load_mesh(mesh)[0][::7]
    W, T = random_weights(rng, len(V), m), rigid_transforms(rng, m)
    U = dqs(V, W, T)
    assert U.shape == V.shape and U.dtype == np.float64
    np.testing.assert_allclose(U, libigl_dqs(V, W, T), rtol=0, atol=1e-11 * (np.abs(V).max() + 10))


@settings(max_examples=15, deadline=None)
@given(meshes, st.integers(1, 6), seeds)
def test_one_rigid_transform_for_all_handles_moves_the_mesh_rigidly(mesh, m, seed):
    rng = np.random.default_rng(seed)
    V = load_mesh(mesh)[0]
    T = rigid_transforms(rng, 1)
    U = dqs(V, random_weights(rng, len(V), m), np.tile(T, (m, 1, 1)))
    np.testing.assert_allclose(U, V @ T[0, :, :3].T + T[0, :, 3], rtol=0, atol=1e-12 * (np.abs(V).max() + 10))


@given(st.integers(1, 6), seeds)
def test_vertex_bound_to_one_handle_follows_that_handle_exactly(m, seed):
    rng = np.random.default_rng(seed)
    V, T = rng.normal(size=(m, 3)), rigid_transforms(rng, m)
    U = dqs(V, np.eye(m)[::-1], T)  # vertex i is bound to handle m-1-i only
    expected = np.einsum("iab,ib->ia", T[::-1, :, :3], V) + T[::-1, :, 3]
    np.testing.assert_allclose(U, expected, rtol=0, atol=1e-12 * (np.abs(expected).max() + 1))


@settings(max_examples=10, deadline=None)
@given(st.floats(0.0, 179.0), seeds)
def test_every_vertex_moves_rigidly_so_a_twisted_cylinder_keeps_its_radius(degrees, seed):
    # no candy wrapper: each vertex's blend is a rigid motion, here a turn about the x axis
    V = load_mesh("cylinder")[0]
    W = random_weights(np.random.default_rng(seed), len(V), 2)
    U = dqs(V, W, np.stack([turn_about_x(0.0), turn_about_x(degrees)]))
    np.testing.assert_allclose(np.linalg.norm(U[:, 1:], axis=1), np.linalg.norm(V[:, 1:], axis=1), atol=1e-12)
    np.testing.assert_allclose(U[:, 0], V[:, 0], atol=1e-12)


def test_blend_takes_the_short_way_relative_to_handle_0():
    # handles at +170° and -170° are 20° apart across the half turn: their middle is 180°, not 0°
    V = np.array([[0.0, 1.0, 0.0]])
    U = dqs(V, [[0.5, 0.5]], np.stack([turn_about_x(170.0), turn_about_x(-170.0)]))
    np.testing.assert_allclose(U, [[0.0, -1.0, 0.0]], atol=1e-12)


def test_twisted_blend_preserves_distances_to_the_axis_but_not_to_each_other():
    V = load_mesh("cylinder")[0]
    s = (V[:, 0] - V[:, 0].min()) / np.ptp(V[:, 0])
    U = dqs(V, np.c_[1 - s, s], np.stack([turn_about_x(0.0), turn_about_x(90.0)]))
    assert not np.allclose(pdist(U), pdist(V), atol=1e-3)  # the twist bends the shape, it is no rigid motion


def test_inputs_are_not_modified():
    rng = np.random.default_rng(4)
    V = load_mesh("bar_coarse")[0]
    W, T = random_weights(rng, len(V), 3), rigid_transforms(rng, 3)
    copies = V.copy(), W.copy(), T.copy()
    dqs(V, W, T)
    for before, after in zip(copies, (V, W, T)):
        np.testing.assert_array_equal(before, after)


V_OK = np.arange(12.0).reshape(4, 3)
W_OK = np.full((4, 2), 0.5)
T_OK = np.tile(np.eye(3, 4), (2, 1, 1))


@pytest.mark.parametrize(
    "V, W, T, message",
    [
        (V_OK[:, :2], W_OK, T_OK, "V must have 3 columns"),
        (V_OK, W_OK[:3], T_OK, r"W must have shape \(4, m\), one row per vertex of V .* got \(3, 2\)"),
        (V_OK, np.zeros((4, 0)), T_OK[:0], r"W must have shape \(4, m\)"),
        (V_OK, W_OK, T_OK[:1], r"T must have shape \(2, 3, 4\), one rigid transform per column of W, got \(1, 3, 4\)"),
        (V_OK, W_OK, T_OK * 2.0, r"T\[0\] is not rigid"),
        (V_OK, np.r_[W_OK[:3], [[0.0, 0.0]]], T_OK, r"W\[3\] blends the handles' rotations to zero"),
        (V_OK, np.where(W_OK > 0, np.nan, 0.0), T_OK, "W contains NaN or inf"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, W, T, message):
    with pytest.raises(ValueError, match=message):
        dqs(V, W, T)
