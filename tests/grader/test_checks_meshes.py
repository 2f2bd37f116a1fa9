"""The stage 00 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import igl
import numpy as np
import pytest

import reference.meshes as ref
from grader.checks import check_namespace
from deformlab_packs.deformation.checks.generators import clockwise, closed_mesh_with_hole, disjoint_union, mixed_orientation, perforated_slab, relabel, similar_copy, unsorted_order
from deformlab_packs.deformation.checks.meshes import _topology_meshes
from starter import shapes


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def failed(result):
    return result.failed_verdicts()


def _half_edges(F):
    return np.asarray(F)[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2)


def edges_with_unsorted_rows(F):
    E = _half_edges(F)
    _, first = np.unique(np.sort(E, axis=1), axis=0, return_index=True)
    return E[first]


def edges_with_duplicates(F):
    E = np.sort(_half_edges(F), axis=1)
    return E[np.lexsort(E.T[::-1])]


def edges_unordered(F):
    return np.unique(np.sort(_half_edges(F), axis=1), axis=0)[::-1]


def boundary_loops_of_directed_half_edges(F):
    """Loops traced along the half-edges whose reverse is missing: right on consistently oriented meshes only."""
    half_edges = {(int(a), int(b)) for a, b in _half_edges(F)}
    following = {a: b for a, b in half_edges if (b, a) not in half_edges}
    loops = 0
    while following:
        start, vertex = following.popitem()
        while vertex != start and vertex in following:
            vertex = following.pop(vertex)
        loops += 1
    return loops


@pytest.mark.parametrize(
    "function, implementation, verdict",
    [
        ("edges", edges_with_unsorted_rows, "rows sorted ascending"),
        ("edges", edges_with_duplicates, "rows in lexicographic order, each edge once"),
        ("edges", edges_unordered, "rows in lexicographic order, each edge once"),
        ("euler_characteristic", lambda V, F: len(V) - 3 * len(F) + len(F), "Euler characteristic value"),
        ("boundary_loop_count", lambda F: int(np.sum(np.unique(np.sort(_half_edges(F), 1), axis=0, return_counts=True)[1] == 1)), "boundary loop count value"),
        ("boundary_loop_count", lambda F: int(ref.boundary_loop_count(F) > 0), "boundary loop count value"),
        ("genus", lambda V, F: (2 - ref.boundary_loop_count(F) - ref.euler_characteristic(V, F)) // 2, "genus value"),
        ("genus", lambda V, F: (2 - ref.euler_characteristic(V, F)) // 2, "genus value"),
        ("boundary_loop_count", boundary_loops_of_directed_half_edges, "boundary loop count value"),
    ],
    ids=[
        "edges: rows not sorted",
        "edges: each half-edge kept",
        "edges: rows in descending order",
        "euler: half-edges counted as edges",
        "boundary: boundary edges counted instead of loops",
        "boundary: at most one loop",
        "genus: one component assumed",
        "genus: boundaries ignored",
        "boundary: half-edges without a reverse twin, as if all triangles were oriented alike",
    ],
)
def test_realistic_mistakes_fail(function, implementation, verdict):
    assert verdict in failed(grade(function, implementation))


def test_edge_count_and_edges_are_checked_against_the_mesh():
    def missing_one(F):
        return ref.edges(F)[1:]

    assert {"edge count", "same edges as the mesh"} <= failed(grade("edges", missing_one))


def test_hidden_meshes_have_the_topology_their_labels_say():
    rng = np.random.default_rng(4)
    V, F = relabel(*perforated_slab(2), rng)
    assert ref.genus(V, F) == 2 and ref.boundary_loop_count(F) == 0
    # Consistently oriented: every directed half-edge of a closed surface occurs exactly once.
    half_edges = F[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
    assert len(np.unique(half_edges, axis=0)) == len(half_edges)
    V, F = closed_mesh_with_hole(*shapes.torus(n_major=6, n_minor=4), rng)
    assert ref.genus(V, F) == 1 and ref.boundary_loop_count(F) == 1
    V, F = disjoint_union(shapes.torus(n_major=6, n_minor=4), shapes.torus(n_major=5, n_minor=3))
    assert ref.genus(V, F) == 2


def test_relabel_keeps_each_triangle_and_its_orientation():
    rng = np.random.default_rng(5)
    V, F = shapes.torus(n_major=6, n_minor=4)
    V2, F2 = relabel(V, F, rng)

    def oriented_triangles(V, F):
        """Each triangle's corner positions, rotated to start at the smallest: the same for a relabelled mesh."""
        out = []
        for t in V[F]:
            k = min(range(3), key=lambda s: tuple(t[s]))
            out.append(tuple(np.roll(t, -k, axis=0).ravel()))
        return sorted(out)

    assert oriented_triangles(V, F) == oriented_triangles(V2, F2)


def test_hidden_2d_meshes_come_clockwise_counter_clockwise_and_mixed():
    orientations = set()
    for label, V, F in _topology_meshes(np.random.default_rng(6)):
        if V.shape[1] == 2:
            area = igl.doublearea(V, F)  # signed for 2D input
            orientations.add("mixed" if (area > 0).any() and (area < 0).any() else "ccw" if (area > 0).all() else "cw")
    assert orientations == {"ccw", "cw", "mixed"}


def test_orientation_helpers_keep_the_triangles_and_reverse_what_they_say():
    rng = np.random.default_rng(7)
    V, F = shapes.grid_2d(4, 3)
    assert (igl.doublearea(V, clockwise(F)) < 0).all()
    mixed = mixed_orientation(F, rng)
    flipped = igl.doublearea(V, mixed) < 0
    assert 0 < flipped.sum() < len(F)
    assert np.array_equal(np.sort(mixed, axis=1), np.sort(F, axis=1))


def test_a_similar_copy_scales_distances_and_moves_the_centroid():
    rng = np.random.default_rng(8)
    V, F = shapes.grid_2d(3, 3)
    move = similar_copy(rng, 2, 0.01, 20.0)
    W = move(V)
    assert (igl.doublearea(W, F) > 0).all()  # turned, never mirrored
    assert np.allclose(np.linalg.norm(W[1:] - W[0], axis=1), 0.01 * np.linalg.norm(V[1:] - V[0], axis=1))
    assert np.isclose(np.linalg.norm(move(np.zeros((1, 2)))), 20.0)


def test_handle_orders_are_never_ascending():
    rng = np.random.default_rng(11)
    for _ in range(50):
        for items in (2, 3, np.array([0, 4, 5]), np.array([7, 9])):
            order = unsorted_order(rng, items)
            assert not np.all(np.diff(order) > 0)
            assert sorted(order.tolist()) == (list(range(items)) if np.ndim(items) == 0 else sorted(items.tolist()))
