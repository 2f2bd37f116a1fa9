"""Checks of stage 00 (edges and the Euler–Poincaré formula), and the hidden test meshes.

The mesh helpers here (``relabel``, ``disjoint_union``, ``jittered_grid``,
``perforated_slab``, ``closed_mesh_with_hole``, ``clockwise``, ``mixed_orientation``,
``similar_copy``, ``unsorted_order``) are also used by the later stages' checks, so every stage draws its
hidden meshes the same way: a small mesh from ``starter.shapes`` with its
vertices, triangles and corners shuffled by the run's generator, so that no
output can be memorized from the handout. The contract fixes no orientation,
labelling or placement, so the hidden meshes use that freedom: clockwise as well
as counter-clockwise 2D triangles (whole meshes, single components, or
triangle by triangle), and copies of a whole problem scaled and moved far from
the origin. An implementation right on the handout's counter-clockwise meshes
only loses points.
"""

from __future__ import annotations

import numpy as np

from grader.checks.base import Case, FunctionChecks, as_array, as_int, verdict
from starter import shapes
from starter.meshes import load_mesh


def relabel(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The same mesh with vertices and triangles in random order and each triangle's corners rotated.

    Parameters
    ----------
    V : (n, d) numpy.ndarray
    F : (f, 3) numpy.ndarray of int
    rng : numpy.random.Generator

    Returns
    -------
    V : (n, d) numpy.ndarray of float64
    F : (f, 3) numpy.ndarray of int64
        Same orientation as the input (corners are rotated cyclically, never swapped).
    """
    order = rng.permutation(len(V))
    new_index = np.empty_like(order)
    new_index[order] = np.arange(len(V))
    F = new_index[np.asarray(F)][rng.permutation(len(F))]
    shift = rng.integers(0, 3, len(F))
    F = F[np.arange(len(F))[:, None], (np.arange(3) + shift[:, None]) % 3]
    return np.ascontiguousarray(V[order], dtype=np.float64), np.ascontiguousarray(F, dtype=np.int64)


def clockwise(F: np.ndarray) -> np.ndarray:
    """Every triangle with its corners in reverse order: a counter-clockwise 2D mesh becomes clockwise.

    Parameters
    ----------
    F : (f, 3) numpy.ndarray of int

    Returns
    -------
    (f, 3) numpy.ndarray of int64
        Same triangles, same corner positions, opposite orientation.
    """
    return np.ascontiguousarray(np.asarray(F)[:, ::-1], dtype=np.int64)


def mixed_orientation(F: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """About half of the triangles, drawn at random, with their corners in reverse order.

    The contract does not ask for consistently oriented triangles; a mesh read from
    some exporters has them in either order, and none of its quantities (edges,
    boundary loops, cotangents, energies) may depend on it.

    Returns
    -------
    (f, 3) numpy.ndarray of int64
    """
    F = np.array(F, dtype=np.int64)
    flip = rng.uniform(size=len(F)) < 0.5
    F[flip] = F[flip][:, ::-1]
    return F


def unsorted_order(rng: np.random.Generator, items) -> np.ndarray:
    """``items`` (a 1-D array, or a count ``k`` for ``range(k)``) in random order, never ascending when there are two or more.

    Handles in ascending order would hide an implementation that sorts them,
    e.g. by ``np.unique``.
    """
    order = rng.permutation(items)
    if len(order) > 1 and np.all(np.diff(order) > 0):
        order = order[::-1]
    return order


def similar_copy(rng: np.random.Generator, d: int, scale: float, distance: float):
    """A map ``x -> scale · R x + t`` of ``(k, d)`` points: ``R`` a random rotation, ``‖t‖ = distance``.

    Applied to every position of a problem (rest mesh, handle targets) it gives
    the same problem at another size and place; a rotation, never a
    reflection, so triangles keep their orientation.
    """
    from grader.checks.shape_matching import random_rotation

    R = random_rotation(rng, d)
    t = rng.normal(size=d)
    t *= distance / np.linalg.norm(t)
    return lambda X: scale * np.asarray(X, dtype=np.float64) @ R.T + t


def disjoint_union(*meshes: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Several meshes of the same dimension as one mesh with several connected components.

    Parameters
    ----------
    *meshes : (V, F) pairs
        ``V`` ``(n_k, d)``, ``F`` ``(f_k, 3)``.

    Returns
    -------
    V : (Σ n_k, d) numpy.ndarray of float64
    F : (Σ f_k, 3) numpy.ndarray of int64
    """
    offsets = np.cumsum([0] + [len(V) for V, _ in meshes])
    V = np.concatenate([V for V, _ in meshes]).astype(np.float64)
    F = np.concatenate([np.asarray(F) + o for (_, F), o in zip(meshes, offsets)]).astype(np.int64)
    return V, F


def perforated_slab(n_holes: int, max_area: float = 0.03) -> tuple[np.ndarray, np.ndarray]:
    """Closed surface of genus ``n_holes``: ``starter.shapes.disc_with_holes`` extruded to thickness 0.2.

    Returns
    -------
    V : (2 n, 3) numpy.ndarray of float64
        The disc's ``n`` vertices at ``z = 0``, then again at ``z = 0.2``.
    F : (f, 3) numpy.ndarray of int64
        Bottom (flipped), top and a wall of two triangles per boundary edge,
        consistently oriented.
    """
    V2, F2 = shapes.disc_with_holes(n_holes, max_area)
    n = len(V2)
    half_edges = F2[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2)
    key = np.sort(half_edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    a, b = half_edges[counts[inverse.ravel()] == 1].T  # boundary edges as the top triangles run them
    # Quad a, b, b', a' runs each edge against the bottom's and the top's triangles.
    walls = np.concatenate([np.stack([a, b, b + n], 1), np.stack([a, b + n, a + n], 1)])
    V = np.concatenate([np.c_[V2, np.zeros(n)], np.c_[V2, np.full(n, 0.2)]])
    return V, np.concatenate([F2[:, ::-1], F2 + n, walls]).astype(np.int64)


def jittered_grid(rng: np.random.Generator, nx: int, ny: int, width: float = 1.0, height: float = 1.0, amount: float = 0.3) -> tuple[np.ndarray, np.ndarray]:
    """``starter.shapes.grid_2d`` with interior vertices moved by up to ``amount`` cells: obtuse triangles, negative cotangents.

    Returns
    -------
    V : ((nx + 1)(ny + 1), 2) numpy.ndarray of float64
    F : (2 nx ny, 3) numpy.ndarray of int64
        Still counter-clockwise for ``amount < 0.5``.
    """
    V, F = shapes.grid_2d(nx, ny, width=width, height=height)
    interior = np.all((V > 0.0) & (V < [width, height]), axis=1)
    V[interior] += rng.uniform(-amount, amount, (int(interior.sum()), 2)) * [width / nx, height / ny]
    return V, F


def closed_mesh_with_hole(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A closed mesh with one random triangle removed: one boundary loop, same genus.

    Returns
    -------
    V : (n, d) numpy.ndarray
        ``V`` itself (every vertex of a closed mesh keeps other triangles).
    F : (f - 1, 3) numpy.ndarray
    """
    return V, np.delete(F, rng.integers(len(F)), axis=0)


def _topology_meshes(rng: np.random.Generator) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Closed, bounded, multi-component and higher-genus meshes (small ``starter.shapes`` and course meshes), shuffled."""
    grid = shapes.grid_2d(int(rng.integers(2, 5)), 2)
    disc = shapes.disc_with_holes(int(rng.integers(1, 4)), 0.03)
    meshes = [
        ("torus", *shapes.torus(n_major=int(rng.integers(8, 14)), n_minor=int(rng.integers(5, 8)))),
        ("2D disc with holes", *disc),
        ("2D disc with holes, clockwise triangles", disc[0], clockwise(disc[1])),
        (
            "two 2D components, one clockwise and one counter-clockwise: a disc with holes and a grid",
            *disjoint_union((disc[0], clockwise(disc[1])), (grid[0] + [3.0, 0.0], grid[1])),
        ),
        ("2D grid, each triangle in either orientation", grid[0], mixed_orientation(grid[1], rng)),
        ("sphere", *load_mesh("sphere")),
        ("closed bar", *load_mesh("bar_coarse")),
        ("genus-2 slab", *perforated_slab(2)),
        ("open tube", *shapes.cylinder(n_around=int(rng.integers(5, 10)), n_along=3, caps=False)),
        ("15 closed components (ant)", *load_mesh("ant")),
        (
            "three components: capped cylinder, torus with a hole, 2D grid lifted to 3D",
            *disjoint_union(
                shapes.cylinder(n_around=6, n_along=2),
                closed_mesh_with_hole(*shapes.torus(n_major=8, n_minor=5), rng),
                (np.c_[grid[0], np.zeros(len(grid[0]))], grid[1]),
            ),
        ),
    ]
    return [(label, *relabel(np.asarray(V, float), np.asarray(F), rng)) for label, V, F in meshes]


def _integer_verdict(got, expected, what: str) -> list:
    value = as_int(got, what)
    want = as_int(expected, "the reference's output")
    return [verdict(f"{what} value", value == want, f"returned {value}, expected {want}")]


class EdgesChecks(FunctionChecks):
    function = "edges"
    description = "each undirected edge once, rows sorted, rows in lexicographic order, on closed, bounded and multi-component meshes, triangles in either orientation"

    def cases(self, rng):
        return [Case.call(label, "edges", F) for label, _, F in _topology_meshes(rng)]

    def verify(self, case, got, expected):
        integer = np.issubdtype(np.asarray(got).dtype, np.integer)
        E = as_array(got, (None, 2), "edges", dtype=np.int64)
        want = as_array(expected, (None, 2), "the reference's edges", dtype=np.int64)
        unsorted = np.flatnonzero(E[:, 0] >= E[:, 1])
        # Strictly increasing rows: lexicographic order and no duplicates in one test.
        step = np.diff(E, axis=0)
        disorder = np.flatnonzero((step[:, 0] < 0) | ((step[:, 0] == 0) & (step[:, 1] <= 0)))
        found = {tuple(e) for e in np.sort(E, axis=1).tolist()}
        wanted = {tuple(e) for e in want.tolist()}
        missing, extra = sorted(wanted - found), sorted(found - wanted)
        verdicts = [
            verdict("integer indices", integer, f"edges have dtype {np.asarray(got).dtype}; vertex indices are integers (int64)"),
            verdict("edge count", len(E) == len(want), f"returned {len(E)} rows, the mesh has {len(want)} edges"),
        ]
        detail = f"row {unsorted[0]} is {E[unsorted[0]].tolist()}" if unsorted.size else ""
        verdicts.append(verdict("rows sorted ascending", unsorted.size == 0, detail))
        detail = f"rows {disorder[0]} and {disorder[0] + 1} are {E[disorder[0]].tolist()} and {E[disorder[0] + 1].tolist()}" if disorder.size else ""
        verdicts.append(verdict("rows in lexicographic order, each edge once", disorder.size == 0, detail))
        detail = []
        if missing:
            detail.append(f"{len(missing)} edge(s) of the mesh missing, e.g. {list(missing[0])}")
        if extra:
            detail.append(f"{len(extra)} row(s) not an edge of the mesh, e.g. {list(extra[0])}")
        verdicts.append(verdict("same edges as the mesh", not detail, "; ".join(detail)))
        return verdicts


class EulerCharacteristicChecks(FunctionChecks):
    function = "euler_characteristic"
    description = "V - E + F on closed, bounded, multi-component and higher-genus meshes"

    def cases(self, rng):
        return [Case.call(label, "euler_characteristic", V, F) for label, V, F in _topology_meshes(rng)]

    def verify(self, case, got, expected):
        return _integer_verdict(got, expected, "Euler characteristic")


class BoundaryLoopCountChecks(FunctionChecks):
    function = "boundary_loop_count"
    description = "number of boundary loops: 0 on closed meshes, one per hole and per outer boundary otherwise, whatever the triangles' orientation"

    def cases(self, rng):
        return [Case.call(label, "boundary_loop_count", F) for label, _, F in _topology_meshes(rng)]

    def verify(self, case, got, expected):
        return _integer_verdict(got, expected, "boundary loop count")


class GenusChecks(FunctionChecks):
    function = "genus"
    description = "genus from χ = 2(c - g) - b, with boundaries and several components"

    def cases(self, rng):
        return [Case.call(label, "genus", V, F) for label, V, F in _topology_meshes(rng)]

    def verify(self, case, got, expected):
        return _integer_verdict(got, expected, "genus")
