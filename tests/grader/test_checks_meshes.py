"""The stage 00 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import numpy as np
import pytest

import reference.meshes as ref
from grader.checks import check_namespace
from grader.checks.meshes import closed_mesh_with_hole, disjoint_union, perforated_slab, relabel
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
