from functools import lru_cache

import igl
import igl.triangle
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.bounded_biharmonic_weights import bbw, biharmonic_matrix, handle_constraints, unconstrained_biharmonic_weights
from starter.meshes import load_handles, load_mesh
from starter.shapes import character_2d, character_2d_handles

seeds = st.integers(0, 2**32 - 1)
KINDS = ["points", "bones", "regions"]


@lru_cache(maxsize=None)
def small_character():
    """The 2D character with ~550 vertices and its handle sets."""
    V, F = character_2d(max_area=0.003)
    return V, F, character_2d_handles(V)


def handle_list(handles, kind):
    return [[i] for i in handles["points"]] if kind == "points" else list(handles[kind])


def libigl_bbw(V, F, b, bc):
    W = igl.bbw(V, F, b, bc)
    return W / W.sum(axis=1, keepdims=True)


def blob_with_point_handles(max_area=0.002):
    """Triangle mesh of a rounded blob; its first three vertices are interior handle points."""
    t = np.linspace(0.0, 2.0 * np.pi, 120, endpoint=False)
    r = 1.0 + 0.25 * np.cos(3 * t)
    outline = np.c_[r * np.cos(t), 0.7 * r * np.sin(t)]
    points = np.array([[0.7, 0.0], [-0.35, 0.45], [-0.35, -0.45]])
    loop = 3 + np.c_[np.arange(len(t)), (np.arange(len(t)) + 1) % len(t)]
    V, F, *_ = igl.triangle.triangulate(np.vstack([points, outline]), loop, flags=f"pq30a{max_area}Q")
    np.testing.assert_array_equal(V[:3], points)
    return V, F, np.arange(3)


def projected_gradient(Q, w, b):
    """KKT residual of min ½ wᵀQw s.t. 0 ≤ w ≤ 1 on the vertices not in ``b``.

    The gradient ``Q w`` must vanish where ``0 < w < 1``, be ``≥ 0`` where
    ``w = 0`` and ``≤ 0`` where ``w = 1``.
    """
    g = Q @ w
    g = np.where(w <= 1e-9, np.minimum(g, 0.0), np.where(w >= 1.0 - 1e-9, np.maximum(g, 0.0), g))
    return np.delete(g, b)


def unnormalized_column(V, F, b, bc, j):
    """Handle ``j``'s weights before normalization, through ``bbw`` itself.

    With the two columns ``bc[:, j]`` and ``1 - bc[:, j]`` the second problem
    is the first one under ``w -> 1 - w`` (``Q 1 = 0``), so the two weights sum
    to one and normalizing leaves the first column as it was.
    """
    W2 = bbw(V, F, b, np.c_[bc[:, j], 1.0 - bc[:, j]])
    np.testing.assert_allclose(W2.sum(axis=1), 1.0, atol=1e-9)
    return W2[:, 0]


def test_matches_libigl_on_the_character_with_point_handles():
    V, F = load_mesh("character")
    b, bc = handle_constraints([[i] for i in load_handles("character")["points"]])
    np.testing.assert_allclose(bbw(V, F, b, bc), libigl_bbw(V, F, b, bc), atol=1e-4)


def test_matches_libigl_on_a_fresh_triangle_mesh():
    V, F, points = blob_with_point_handles()
    b, bc = handle_constraints([[i] for i in points])
    np.testing.assert_allclose(bbw(V, F, b, bc), libigl_bbw(V, F, b, bc), atol=1e-4)


@pytest.mark.parametrize("kind", KINDS)
def test_matches_libigl_with_points_bones_and_regions(kind):
    V, F, handles = small_character()
    b, bc = handle_constraints(handle_list(handles, kind))
    np.testing.assert_allclose(bbw(V, F, b, bc), libigl_bbw(V, F, b, bc), atol=1e-4)


def test_matches_libigl_on_a_closed_surface():
    V, F = load_mesh("bar_coarse")
    handles = load_handles("bar_coarse")
    b, bc = handle_constraints([handles["left"], handles["right"]])
    W = bbw(V, F, b, bc)
    np.testing.assert_allclose(W, libigl_bbw(V, F, b, bc), atol=1e-4)
    assert W.min() >= 0.0 and W.max() <= 1.0


@st.composite
def character_handles(draw):
    """A random non-empty mix of the small character's point, bone and region handles."""
    _, _, handles = small_character()
    kind = draw(st.sampled_from(KINDS))
    pool = handle_list(handles, kind)
    chosen = draw(st.lists(st.integers(0, len(pool) - 1), min_size=1, max_size=len(pool), unique=True))
    return [pool[i] for i in chosen]


@settings(max_examples=20, deadline=None)
@given(character_handles())
def test_weights_are_bounded_sum_to_one_and_meet_the_constraints(handles):
    V, F, _ = small_character()
    b, bc = handle_constraints(handles)
    W = bbw(V, F, b, bc)
    assert W.shape == (len(V), len(handles))
    assert W.min() >= -1e-9 and W.max() <= 1.0 + 1e-9
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(W[b], bc, atol=1e-9)


@settings(max_examples=20, deadline=None)
@given(seeds, st.integers(2, 5))
def test_weights_of_random_point_handles_are_bounded_and_sum_to_one(seed, count):
    V, F, _ = small_character()
    b = np.random.default_rng(seed).choice(len(V), size=count, replace=False)
    W = bbw(V, F, b, np.eye(count))
    assert W.min() >= -1e-9 and W.max() <= 1.0 + 1e-9
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(W[b], np.eye(count), atol=1e-9)


@settings(max_examples=8, deadline=None)
@given(character_handles())
def test_each_unnormalized_column_satisfies_the_kkt_conditions(handles):
    V, F, _ = small_character()
    b, bc = handle_constraints(handles)
    Q = biharmonic_matrix(V, F)
    scale = abs(Q).sum(axis=1).max()
    columns = np.column_stack([unnormalized_column(V, F, b, bc, j) for j in range(len(handles))])
    assert columns.min() >= -1e-9 and columns.max() <= 1.0 + 1e-9
    np.testing.assert_allclose(columns[b], bc, atol=1e-9)
    for w in columns.T:
        assert np.abs(projected_gradient(Q, w, b)).max() <= 1e-9 * scale
    # bbw is these columns with the rows normalized
    np.testing.assert_allclose(bbw(V, F, b, bc), columns / columns.sum(axis=1, keepdims=True), atol=1e-9)


def test_matches_libigl_on_the_tet_hand_with_bones():
    V, T = load_mesh("hand_tet")
    b, bc = handle_constraints(load_handles("hand_tet")["bones"])
    W = bbw(V, T, b, bc)
    np.testing.assert_allclose(W, libigl_bbw(V, T, b, bc), atol=1e-8)
    assert W.min() >= 0.0 and W.max() <= 1.0
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-12)


def test_tet_weights_of_the_palm_against_the_thumb_satisfy_the_kkt_conditions():
    V, T = load_mesh("hand_tet")
    bones = load_handles("hand_tet")["bones"]
    b, bc = handle_constraints([bones[0], bones[5]])
    Q = biharmonic_matrix(V, T)
    w = unnormalized_column(V, T, b, bc, 0)
    assert w.min() >= -1e-9 and w.max() <= 1.0 + 1e-9
    assert np.abs(projected_gradient(Q, w, b)).max() <= 1e-9 * abs(Q).sum(axis=1).max()


def test_clipped_unconstrained_weights_fail_the_kkt_check():
    # the KKT test above can fail: clipping is not the bounded minimizer
    V, F, handles = small_character()
    b, bc = handle_constraints(handle_list(handles, "points"))
    Q = biharmonic_matrix(V, F)
    clipped = np.clip(unconstrained_biharmonic_weights(V, F, b, bc), 0.0, 1.0)
    residual = max(np.abs(projected_gradient(Q, w, b)).max() for w in clipped.T)
    assert residual > 1e-6 * abs(Q).sum(axis=1).max()


def test_bounds_remove_the_negative_lobes():
    V, F = load_mesh("character")
    b, bc = handle_constraints([[i] for i in load_handles("character")["points"]])
    lobes = unconstrained_biharmonic_weights(V, F, b, bc) < -0.01
    assert lobes.any()
    W = bbw(V, F, b, bc)
    assert W.min() >= -1e-9
    # the lower bound is active on most of the lobes
    assert np.mean(W[lobes] <= 1e-9) > 0.5


def test_a_single_handle_weighs_one_everywhere():
    V, F, handles = small_character()
    b, bc = handle_constraints([handles["bones"][0]])
    np.testing.assert_array_equal(bbw(V, F, b, bc), 1.0)


def test_inputs_are_not_modified():
    V, F, handles = small_character()
    b, bc = handle_constraints(handle_list(handles, "regions"))
    copies = [x.copy() for x in (V, F, b, bc)]
    bbw(V, F, b, bc)
    for x, x0 in zip((V, F, b, bc), copies):
        np.testing.assert_array_equal(x, x0)


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
        ([0, 5], [[1.0, 0.0], [1.5, 0.0]], r"bc must lie in \[0, 1\].*bc\[1, 0\] = 1.5"),
        ([0, 5], [[1.0, 0.0], [-0.5, 1.0]], r"bc must lie in \[0, 1\].*bc\[1, 0\] = -0.5"),
        ([0, 5], [[1.0, 0.0], [0.0, 0.0]], "bc must have rows with a positive sum.*row 1"),
    ],
)
def test_bad_constraints_raise_value_error_naming_the_argument(b, bc, message):
    V, F, _ = small_character()
    with pytest.raises(ValueError, match=message):
        bbw(V, F, np.asarray(b), bc)


def test_a_component_without_handles_is_rejected():
    V, F, _ = small_character()
    V2, F2 = np.vstack([V, V + [3.0, 0.0]]), np.vstack([F, F + len(V)])
    with pytest.raises(ValueError, match="b must contain a vertex of every connected component"):
        bbw(V2, F2, np.array([0, 1]), np.eye(2))


@pytest.mark.parametrize(
    "V, F, message",
    [
        (np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), np.array([[0, 1, 2]]), "F has a zero-area triangle"),
        (np.eye(3), np.array([[0, 1, 3]]), "F has a vertex index out of range"),
        (np.ones((3, 4)), np.array([[0, 1, 2]]), "V must have 2 or 3 columns"),
        (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "F must be an integer array"),
        (np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [5.0, 5.0]]), np.array([[0, 1, 2]]), "V has an unreferenced vertex"),
        (np.eye(4)[:, :2], np.array([[0, 1, 2, 3]]), r"V must have shape \(n, 3\) for a tetrahedral mesh"),
        (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]), np.array([[0, 1, 2, 3]]), "F has a flat tetrahedron"),
        (np.eye(3), np.array([[0, 1, 2, 0, 1]]), r"F must have shape \(f, 3\) \(triangles\) or \(f, 4\)"),
    ],
)
def test_bad_meshes_raise_value_error_naming_the_argument(V, F, message):
    with pytest.raises(ValueError, match=message):
        bbw(V, F, np.array([0]), np.ones((1, 1)))
