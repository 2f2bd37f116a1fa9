import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import cotangent_weights
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "torus", "character", "disc_with_holes"])


def edge_vectors(V, F):
    """``(f, 3, d)``: the edge opposite each corner."""
    return V[np.roll(F, -1, axis=1)] - V[np.roll(F, -2, axis=1)]


def double_areas(V, F):
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    if V.shape[1] == 2:
        return np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return np.linalg.norm(np.cross(e1, e2), axis=1)


def test_equilateral_and_right_triangles_have_known_weights():
    F = np.array([[0, 1, 2]])
    equilateral = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, np.sqrt(3.0) / 2.0]])
    np.testing.assert_allclose(cotangent_weights(equilateral, F), np.full((1, 3), 0.5 / np.sqrt(3.0)), atol=1e-15)
    # right angle at corner 0, 45 degrees at corners 1 and 2
    right = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    np.testing.assert_allclose(cotangent_weights(right, F), [[0.0, 0.5, 0.5]], atol=1e-15)
    # an obtuse angle (120 degrees at corner 2) gives a negative weight
    obtuse = np.array([[0.0, 0.0], [np.sqrt(3.0), 0.0], [np.sqrt(3.0) / 2.0, 0.5]])
    np.testing.assert_allclose(cotangent_weights(obtuse, F), [[0.5 * np.sqrt(3.0), 0.5 * np.sqrt(3.0), -0.5 / np.sqrt(3.0)]], atol=1e-14)


@settings(max_examples=30, deadline=None)
@given(meshes)
def test_weighted_squared_edge_lengths_sum_to_the_area_of_each_triangle(mesh):
    # Σ_k cot α_k |e_k|² = 4 A (Heron's formula), so Σ_k C_k |e_k|² = 2 A
    V, F = load_mesh(mesh)
    C = cotangent_weights(V, F)
    E = edge_vectors(V, F)
    np.testing.assert_allclose(np.sum(C * np.sum(E * E, axis=2), axis=1), double_areas(V, F), rtol=1e-12)


@settings(max_examples=30, deadline=None)
@given(meshes)
def test_each_weight_is_half_the_cotangent_of_its_corner_angle(mesh):
    V, F = load_mesh(mesh)
    C = cotangent_weights(V, F)
    for k in range(3):
        u = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        v = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        cos = np.sum(u * v, axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        angle = np.arccos(np.clip(cos, -1.0, 1.0))
        np.testing.assert_allclose(C[:, k], 0.5 / np.tan(angle), rtol=1e-9, atol=1e-12)


@settings(max_examples=50, deadline=None)
@given(st.sampled_from(["bar_coarse", "character"]), st.floats(1e-3, 1e3), seeds)
def test_rotations_translations_and_scaling_leave_the_weights_unchanged(mesh, scale, seed):
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    moved = scale * V @ special_ortho_group.rvs(d, random_state=rng).T + rng.normal(size=d)
    # translating a shrunk mesh far away costs digits in the edge vectors
    np.testing.assert_allclose(cotangent_weights(moved, F), cotangent_weights(V, F), rtol=0, atol=1e-9)


def test_a_planar_mesh_gets_the_same_weights_in_2d_and_embedded_in_3d():
    V, F = load_mesh("character")
    rng = np.random.default_rng(1)
    V3 = np.c_[V, np.zeros(len(V))] @ special_ortho_group.rvs(3, random_state=rng).T
    np.testing.assert_allclose(cotangent_weights(V3, F), cotangent_weights(V, F), rtol=1e-9, atol=1e-12)


def test_reversing_triangle_orientation_permutes_the_weights_with_the_corners():
    V, F = load_mesh("bar_coarse")
    np.testing.assert_array_equal(cotangent_weights(V, F[:, ::-1]), cotangent_weights(V, F)[:, ::-1])


def test_inputs_are_not_modified():
    V, F = load_mesh("bar_coarse")
    V0, F0 = V.copy(), F.copy()
    cotangent_weights(V, F)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)


V_OK = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]])


@pytest.mark.parametrize(
    "V, F, message",
    [
        (np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]), np.array([[0, 1, 2]]), "F has a zero-area triangle"),
        (V_OK, np.array([[0, 1, 2], [1, 3, 3]]), "F has a triangle with a repeated vertex"),
        (V_OK, np.array([[0, 1, 4]]), "F has a vertex index out of range"),
        (V_OK, np.array([[0.0, 1.0, 2.0]]), "F must be an integer array"),
        (V_OK, np.array([0, 1, 2]), r"F must have shape \(f, 3\)"),
        (np.c_[V_OK, V_OK], np.array([[0, 1, 2]]), "V must have 2 or 3 columns"),
        (np.where(V_OK == 1.0, np.nan, V_OK), np.array([[0, 1, 2]]), "V contains NaN or inf"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(V, F, message):
    with pytest.raises(ValueError, match=message):
        cotangent_weights(V, F)
