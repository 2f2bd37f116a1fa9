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

from .generators import clockwise, closed_mesh_with_hole, disjoint_union, mixed_orientation, perforated_slab, relabel
from starter import shapes
from starter.meshes import load_mesh


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
