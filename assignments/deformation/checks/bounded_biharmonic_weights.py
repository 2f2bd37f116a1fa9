"""Checks of stage 04, bounded biharmonic weights.

``bbw`` is judged by its constraints (bounds, partition of unity, ``W[b] = bc``)
and by optimality: the biharmonic energy ``Σ_j ½ w_jᵀ Q w_j`` of the returned
(normalized) weights must be within 1% of the reference's. Harmonic weights
and clipped unconstrained biharmonic weights satisfy the constraints but not
this (``tests/grader/test_checks_bbw.py`` shows it on these cases).
"""

from __future__ import annotations

import numpy as np

from .verdicts import sparse_verdict
from grader.checks.base import Case, FunctionChecks, as_array, as_matrix, as_pair, close, max_abs, verdict
from .generators import clockwise, disjoint_union, jittered_grid, mixed_orientation, relabel, similar_copy, unsorted_order
from . import reference
from starter import shapes

#: Relative tolerance of the biharmonic matrix (no solve).
MATRIX_RTOL = 1e-9
#: Bounds, row sums and ``W[b] = bc`` of ``bbw``, absolute (the contract's tolerance).
BOUNDS_TOL = 1e-9
#: Largest relative difference of the biharmonic energy of ``bbw`` weights to the reference's.
ENERGY_RTOL = 0.01
#: Normalized BBW weights are unique; libigl agrees with the reference to ~1e-10, an L-BFGS-B solution to ~3e-6.
WEIGHTS_TOL = 1e-4
#: Unconstrained biharmonic weights against the reference's (a solve: absolute, weights are O(1)).
SOLVE_TOL = 1e-8


def _coarse_disc_with_hole(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Unit disc with an off-centre round hole, about 130 vertices (coarser than ``starter.shapes``' discs)."""
    import igl.triangle

    centre = np.array([rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4)])
    outer, inner = 2.0 * np.pi * np.arange(28) / 28, 2.0 * np.pi * np.arange(10) / 10
    P = np.r_[np.c_[np.cos(outer), np.sin(outer)], centre + 0.3 * np.c_[np.cos(inner), np.sin(inner)]]
    loop = lambda start, k: start + np.c_[np.arange(k), (np.arange(k) + 1) % k]  # noqa: E731
    V, F, *_ = igl.triangle.triangulate(P, np.r_[loop(0, 28), loop(28, 10)], centre[None], flags="pq30a0.02Q")
    return V, F


def handle_scenes(rng: np.random.Generator) -> dict[str, tuple[np.ndarray, np.ndarray, list[np.ndarray]]]:
    """Hidden skinning problems by label: ``(V, F, handles)``, ``handles`` a list of vertex-index arrays.

    Point handles (one vertex), bones (a segment of vertices) and regions
    (discs of vertices), in 2D and 3D, on one or two connected components,
    with vertices and handles in random order; clockwise, counter-clockwise
    and mixed 2D triangles; one problem scaled down and moved far away.
    """
    scenes = {}

    def add(label, V, F, pick, move=None):
        V, F = relabel(V, F, rng)
        handles = [np.asarray(h, dtype=np.int64) for h in pick(V)]  # picked by position, before any move
        scenes[label] = (V if move is None else move(V), F, [handles[j] for j in unsorted_order(rng, len(handles))])

    def near(V, centre, radius):
        return rng.permutation(np.flatnonzero(np.linalg.norm(V - centre, axis=1) <= radius))

    def spread_points(V, k, among=None):
        """``k`` vertices (of ``among``, default all) far apart: farthest-point sampling from a random start."""
        among = np.arange(len(V)) if among is None else among
        chosen = [int(rng.choice(among))]
        for _ in range(k - 1):
            gaps = np.min(np.linalg.norm(V[among, None] - V[chosen][None], axis=2), axis=1)
            chosen.append(int(among[np.argmax(gaps)]))
        return [[i] for i in chosen]

    def close_points(V):
        """Three vertices within 0.2 of each other inside the square, one far away: the weights overshoot between them."""
        first = int(rng.choice(np.flatnonzero(np.all((V > 0.25) & (V < 0.75), axis=1))))
        nearby = np.flatnonzero((np.linalg.norm(V - V[first], axis=1) < 0.2) & (np.arange(len(V)) != first))
        far = int(np.argmax(np.linalg.norm(V - V[first], axis=1)))
        return [[first], *[[int(i)] for i in rng.choice(nearby, 2, replace=False)], [far]]

    def bones(V):
        """Three vertical segments of grid vertices (columns x = 0.4, 1.4, 2.6, 0.25 ≤ y ≤ 0.75)."""
        return [
            rng.permutation(np.flatnonzero(np.isclose(V[:, 0], x) & (V[:, 1] >= 0.25 - 1e-9) & (V[:, 1] <= 0.75 + 1e-9)))
            for x in (0.4, 1.4, 2.6)
        ]

    def regions_and_points(V):
        first, second = near(V, [0.2, 0.2], 0.15), near(V, [0.8, 0.7], 0.15)
        others = np.setdiff1d(np.flatnonzero(np.linalg.norm(V - [0.3, 0.75], axis=1) < 0.25), np.r_[first, second])
        return [first, *[[int(i)] for i in rng.choice(others, 2, replace=False)], second]

    def bar_handles(V):
        x = V[:, 0]
        return [np.flatnonzero(x == x.min()), [int(rng.choice(np.flatnonzero(np.isclose(x, 1.5))))], np.flatnonzero(x == x.max())]

    def two_components(V):
        """A region on the first component (x < 1.5); on the second, three point handles close together inside and one far."""
        right = V[:, 0] > 1.5
        first = int(rng.choice(np.flatnonzero(right & np.all((V > [2.25, 0.25]) & (V < [2.75, 0.75]), axis=1))))
        gaps = np.where(right, np.linalg.norm(V - V[first], axis=1), 0.0)
        nearby = np.flatnonzero(right & (gaps < 0.2) & (np.arange(len(V)) != first))
        return [near(V, [0.5, 0.5], 0.3), [first], *[[int(i)] for i in rng.choice(nearby, 2, replace=False)], [int(np.argmax(gaps))]]

    V, F = _coarse_disc_with_hole(rng)
    add("2D disc with a hole, clockwise triangles, 4 point handles far apart", V, clockwise(F), lambda V: spread_points(V, 4))
    V, F = jittered_grid(rng, 10, 10, 1.0, 1.0)
    add("2D square, triangles in either orientation, 3 point handles close together and one far", V, mixed_orientation(F, rng), close_points)
    add(
        "2D strip, 3 bones, the whole problem scaled by 1/100, turned and moved 10 units away",
        *shapes.grid_2d(15, 8, width=3.0, height=1.0),
        bones,
        similar_copy(rng, 2, 0.01, 10.0),
    )
    add("2D jittered grid, two regions and two points", *jittered_grid(rng, 12, 12, 1.0, 1.0), regions_and_points)
    add("3D bar, regions at both ends and a point in the middle", *shapes.bar(length=3.0, nx=10, ny=3, nz=3), bar_handles)
    square = jittered_grid(rng, 10, 10, 1.0, 1.0)
    add(
        "two 2D components, a region on the counter-clockwise first, close and far point handles on the clockwise second",
        *disjoint_union(shapes.grid_2d(6, 4), (square[0] + [2.0, 0.0], clockwise(square[1]))),
        two_components,
    )
    return scenes


def constraints(handles: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """``(b, bc)`` of ``handles`` as the contract's ``handle_constraints`` defines them (computed here, trusted)."""
    b = np.concatenate(handles).astype(np.int64)
    bc = np.zeros((len(b), len(handles)))
    bc[np.arange(len(b)), np.repeat(np.arange(len(handles)), [len(h) for h in handles])] = 1.0
    return b, bc


def biharmonic_energy(Q, W: np.ndarray) -> float:
    """``Σ_j ½ w_jᵀ Q w_j`` for the columns ``w_j`` of ``W``."""
    return 0.5 * float(np.sum(W * (Q @ W)))


class BiharmonicMatrixChecks(FunctionChecks):
    function = "biharmonic_matrix"
    description = "sparse Q = L M⁻¹ L (Voronoi mass) in 2D and 3D, with thin and obtuse triangles"

    def cases(self, rng):
        meshes = {label: (V, F) for label, (V, F, _) in handle_scenes(rng).items()}
        meshes["2D strip of thin triangles (aspect 50:1)"] = relabel(*shapes.grid_2d(20, 2, width=1.0, height=0.002), rng)
        return [Case.call(label, "biharmonic_matrix", V, F) for label, (V, F) in meshes.items()]

    def verify(self, case, got, expected):
        n = len(case.args()[0])
        Q = as_matrix(got, (n, n), "Q")
        want = as_matrix(expected, (n, n), "the reference's Q")
        ok, where = close(Q, want, MATRIX_RTOL, max_abs(want))
        return [sparse_verdict(got), verdict("Q matches L M⁻¹ L", ok, where)]


class HandleConstraintsChecks(FunctionChecks):
    function = "handle_constraints"
    description = "b the concatenation of the handles in order, bc one-hot in each vertex's handle column, for points, bones and regions"

    def cases(self, rng):
        cases = [Case.call(label, "handle_constraints", handles) for label, (_, _, handles) in handle_scenes(rng).items()]
        single = rng.permutation(40)[:7]
        cases.append(Case.call("one region handle of 7 vertices in random order", "handle_constraints", [single]))
        return cases

    def verify(self, case, got, expected):
        handles = case.args()[0]
        b_got, bc_got = as_pair(got, "(b, bc)")
        b_ref, bc_ref = (np.asarray(x) for x in as_pair(expected, "the reference's (b, bc)"))
        k, m = len(b_ref), len(handles)
        b = as_array(b_got, (k,), "b", dtype=np.int64)
        bc = as_array(bc_got, (k, m), "bc")
        hint = " (b must keep the handles' order, not be sorted)" if np.array_equal(b, np.sort(b_ref)) and not np.array_equal(b, b_ref) else ""
        wrong = np.flatnonzero(b != b_ref)
        i = wrong[0] if wrong.size else 0
        rows = np.flatnonzero(np.any(bc != bc_ref, axis=1))
        r = rows[0] if rows.size else 0
        return [
            verdict("b is the concatenation of the handles", wrong.size == 0, f"b[{i}] = {b[i]}, expected {b_ref[i]}{hint}"),
            verdict("bc one-hot in the handle's column", rows.size == 0, f"bc[{r}] = {bc[r].tolist()}, expected {bc_ref[r].tolist()}"),
        ]


class InverseDistanceWeightsChecks(FunctionChecks):
    function = "inverse_distance_weights"
    description = "Shepard weights ∝ ‖v − h_j‖^-power with rows summing to 1, one-hot within 1e-12 of a handle point"

    def cases(self, rng):
        scenes = handle_scenes(rng)
        V2, _, _ = scenes["2D disc with a hole, clockwise triangles, 4 point handles far apart"]
        V3, _, _ = scenes["3D bar, regions at both ends and a point in the middle"]
        Vg, _, _ = scenes["2D jittered grid, two regions and two points"]
        on_vertices = V2[rng.choice(len(V2), 4, replace=False)]
        off_mesh = rng.normal(0.0, 1.0, (3, 3)) + [1.5, 0.5, 0.5]
        # One handle point 4e-13 from a vertex (one-hot), one 1e-9 from another (not one-hot).
        nudged = Vg[rng.choice(len(Vg), 3, replace=False)] + [[4e-13, 0.0], [0.0, 1e-9], [0.3, 0.3]]
        return [
            Case.call("2D disc, handle points on vertices, default power", "inverse_distance_weights", V2, on_vertices),
            Case.call("3D bar, handle points off the mesh, power 1", "inverse_distance_weights", V3, off_mesh, power=1),
            Case.call("2D grid, a vertex 4e-13 from a handle point, power 3", "inverse_distance_weights", Vg, nudged, 3),
            Case.call("3D bar, a single handle point, power 2.5", "inverse_distance_weights", V3, off_mesh[:1], power=2.5),
            Case.call("2D grid, handle points far outside, power 6", "inverse_distance_weights", Vg, rng.normal(0.0, 30.0, (5, 2)), power=6),
        ]

    def verify(self, case, got, expected):
        V, H = case.args()[:2]
        W = as_array(got, (len(V), len(H)), "W")
        want = as_array(expected, (len(V), len(H)), "the reference's W")
        ok, where = close(W, want, 1e-10)
        return [verdict("W matches", ok, f"{where} (vertex, handle)")]


def _weight_cases(function: str, rng: np.random.Generator) -> list[Case]:
    return [Case.call(label, function, V, F, *constraints(handles)) for label, (V, F, handles) in handle_scenes(rng).items()]


class UnconstrainedBiharmonicWeightsChecks(FunctionChecks):
    function = "unconstrained_biharmonic_weights"
    description = "W minimizing ½ tr(Wᵀ Q W) with W[b] = bc, no bounds, for points, bones and regions in 2D and 3D"

    def cases(self, rng):
        cases = _weight_cases("unconstrained_biharmonic_weights", rng)
        V, F, b, bc = cases[0].args()
        cases.append(Case.call("2D disc, arbitrary values at the handles", "unconstrained_biharmonic_weights", V, F, b, rng.normal(size=bc.shape)))
        return cases

    def verify(self, case, got, expected):
        V, _, b, bc = case.args()
        W = as_array(got, (len(V), bc.shape[1]), "W")
        want = as_array(expected, (len(V), bc.shape[1]), "the reference's W")
        ok_b, where_b = close(W[b], bc, 1e-12)
        ok, where = close(W, want, SOLVE_TOL)
        return [verdict("W[b] = bc", ok_b, where_b), verdict("W matches the minimizer", ok, f"{where} (vertex, handle)")]


class BbwChecks(FunctionChecks):
    function = "bbw"
    description = "0 ≤ W ≤ 1, rows sum to 1, W[b] = bc, biharmonic energy within 1% of the reference's"

    def cases(self, rng):
        return _weight_cases("bbw", rng)

    def verify(self, case, got, expected):
        V, F, b, bc = case.args()
        W = as_array(got, (len(V), bc.shape[1]), "W")
        want = as_array(expected, (len(V), bc.shape[1]), "the reference's W")
        low, high = float(W.min()), float(W.max())
        sums = np.abs(W.sum(axis=1) - 1.0)
        ok_b, where_b = close(W[b], bc / bc.sum(axis=1, keepdims=True), BOUNDS_TOL)
        Q = reference("biharmonic_matrix")(V, F)
        found, best = biharmonic_energy(Q, W), biharmonic_energy(Q, want)
        # Each handle's QP is strictly convex, so the normalized weights are unique: a weak bound or a
        # near-miss solver that the energy alone cannot tell apart still shows here.
        ok_w, where_w = close(W, want, WEIGHTS_TOL)
        return [
            verdict("0 ≤ W ≤ 1", low >= -BOUNDS_TOL and high <= 1.0 + BOUNDS_TOL, f"weights range over [{low:.6g}, {high:.6g}]"),
            verdict("rows sum to 1", sums.max() <= BOUNDS_TOL, f"row {int(np.argmax(sums))} sums to {W.sum(axis=1)[int(np.argmax(sums))]:.12g}"),
            verdict("W[b] = bc", ok_b, where_b),
            verdict(
                "biharmonic energy within 1% of the minimum",
                abs(found - best) <= ENERGY_RTOL * best + 1e-12,
                f"Σ ½ wᵀ Q w is {found:.6g}, the bounded biharmonic weights have {best:.6g} ({(found - best) / max(best, 1e-300):+.1%})",
            ),
            verdict(f"W within {WEIGHTS_TOL:g} of the bounded biharmonic weights", ok_w, where_w),
        ]
