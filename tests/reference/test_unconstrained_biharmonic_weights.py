from functools import lru_cache

import igl
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.bounded_biharmonic_weights import biharmonic_matrix, handle_constraints, unconstrained_biharmonic_weights
from starter.meshes import load_handles, load_mesh
from starter.shapes import character_2d, character_2d_handles

seeds = st.integers(0, 2**32 - 1)
KINDS = ["points", "bones", "regions"]


@lru_cache(maxsize=None)
def small_character():
    """The 2D character with ~550 vertices and its handle sets."""
    V, F = character_2d(max_area=0.003)
    return V, F, character_2d_handles(V)


def character_constraints(kind, mesh="character"):
    V, F = load_mesh(mesh)
    handles = load_handles(mesh)
    b, bc = handle_constraints([[i] for i in handles["points"]] if kind == "points" else handles[kind])
    return V, F, b, bc


def assert_stationary_off_b(V, F, b, W):
    """``Q W = 0`` on the rows not in ``b``, relative to the size of ``Q``'s rows."""
    Q = biharmonic_matrix(V, F)
    free = np.setdiff1d(np.arange(len(V)), b)
    row_scale = abs(Q).sum(axis=1).max() * max(np.abs(W).max(), 1.0)
    assert np.abs((Q @ W)[free]).max() <= 1e-9 * row_scale


@pytest.mark.parametrize("kind", KINDS)
def test_meets_the_constraints_and_is_stationary_elsewhere(kind):
    V, F, b, bc = character_constraints(kind)
    W = unconstrained_biharmonic_weights(V, F, b, bc)
    assert W.shape == (len(V), bc.shape[1])
    np.testing.assert_array_equal(W[b], bc)
    assert_stationary_off_b(V, F, b, W)


@pytest.mark.parametrize("kind", KINDS)
def test_equals_libigl_biharmonic_coordinates(kind):
    V, F, b, bc = character_constraints(kind)
    np.testing.assert_allclose(
        unconstrained_biharmonic_weights(V, F, b, bc), igl.harmonic(V, F, b, bc, 2), atol=1e-8
    )


def test_point_handle_weights_have_negative_lobes_and_overshoots():
    # the artefact that bounded biharmonic weights remove
    V, F, b, bc = character_constraints("points")
    W = unconstrained_biharmonic_weights(V, F, b, bc)
    assert W.min() < -0.01
    assert W.max() > 1.01


@settings(max_examples=15, deadline=None)
@given(seeds, st.integers(2, 6))
def test_weights_of_random_values_at_random_vertices_are_stationary(seed, count):
    V, F, _ = small_character()
    rng = np.random.default_rng(seed)
    b = rng.choice(len(V), size=count, replace=False)
    bc = rng.normal(size=(count, 3))
    W = unconstrained_biharmonic_weights(V, F, b, bc)
    np.testing.assert_array_equal(W[b], bc)
    assert_stationary_off_b(V, F, b, W)


@settings(max_examples=15, deadline=None)
@given(seeds)
def test_weights_of_handles_sum_to_one(seed):
    # Q 1 = 0, so the sum of the columns is the constant that meets Σ bc = 1
    V, F, handles = small_character()
    rng = np.random.default_rng(seed)
    kind = rng.choice(KINDS)
    pool = [[i] for i in handles["points"]] if kind == "points" else handles[kind]
    chosen = rng.choice(len(pool), size=rng.integers(1, len(pool) + 1), replace=False)
    b, bc = handle_constraints([pool[i] for i in chosen])
    W = unconstrained_biharmonic_weights(V, F, b, bc)
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-9)


def test_every_vertex_constrained_returns_bc():
    V, F, _ = small_character()
    bc = np.random.default_rng(0).normal(size=(len(V), 2))
    np.testing.assert_array_equal(unconstrained_biharmonic_weights(V, F, np.arange(len(V)), bc), bc)


def test_inputs_are_not_modified():
    V, F, b, bc = character_constraints("bones")
    copies = [x.copy() for x in (V, F, b, bc)]
    unconstrained_biharmonic_weights(V, F, b, bc)
    for x, x0 in zip((V, F, b, bc), copies):
        np.testing.assert_array_equal(x, x0)


def two_characters():
    V, F, _ = small_character()
    return np.vstack([V, V + [3.0, 0.0]]), np.vstack([F, F + len(V)])


@pytest.mark.parametrize(
    "b, bc, message",
    [
        ([], np.zeros((0, 1)), "b is empty"),
        ([0, 5, 0], np.eye(3), "b has duplicate vertex 0"),
        ([0, 10**6], np.eye(2), r"b\[1\] = 1000000 is out of range"),
        ([0.0, 5.0], np.eye(2), "b must be an integer array"),
        ([0, 5], np.eye(3), r"bc must have shape \(2, m\) with m >= 1: one row per vertex in b"),
        ([0, 5], np.zeros((2, 0)), r"bc must have shape \(2, m\) with m >= 1"),
        ([0, 5], np.ones(2), "bc must be a 2-D array"),
        ([0, 5], [[0.0, np.nan], [1.0, 0.0]], "bc contains NaN or inf"),
    ],
)
def test_bad_constraints_raise_value_error_naming_the_argument(b, bc, message):
    V, F, _ = small_character()
    with pytest.raises(ValueError, match=message):
        unconstrained_biharmonic_weights(V, F, np.asarray(b), bc)


def test_a_component_without_constraints_is_rejected():
    V, F = two_characters()
    with pytest.raises(ValueError, match=r"b must contain a vertex of every connected component"):
        unconstrained_biharmonic_weights(V, F, np.array([0, 1]), np.eye(2))
    # one constrained vertex in each component is enough
    W = unconstrained_biharmonic_weights(V, F, np.array([0, len(V) - 1]), np.eye(2))
    assert np.isfinite(W).all()


@pytest.mark.parametrize(
    "V, F, message",
    [
        (np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), np.array([[0, 1, 2]]), "F has a zero-area triangle"),
        (np.eye(3), np.array([[0, 1, 3]]), "F has a vertex index out of range"),
        (np.ones((3, 4)), np.array([[0, 1, 2]]), "V must have 2 or 3 columns"),
    ],
)
def test_bad_meshes_raise_value_error_naming_the_argument(V, F, message):
    with pytest.raises(ValueError, match=message):
        unconstrained_biharmonic_weights(V, F, np.array([0]), np.ones((1, 1)))
