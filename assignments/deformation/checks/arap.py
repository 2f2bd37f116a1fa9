"""Checks of stage 03, ARAP local–global ("spokes and rims" cells).

Quantities with a unique answer (cotangent weights, Laplacian, covariances,
energies, global-step solutions) are compared with the reference's; the
local step is judged like every rotation (orthonormal, ``det = +1``, optimal
``tr(R_i S_i)``), never by ``R_i`` itself. Energies of the student's
positions are recomputed here with the reference's ``arap_energy``.
"""

from __future__ import annotations

import numpy as np

from grader.checks.base import Case, FunctionChecks, Ref, Step, Verdict, as_array, as_float, as_matrix, as_pair, close, max_abs, verdict
from .generators import clockwise, disjoint_union, jittered_grid, mixed_orientation, relabel, similar_copy, unsorted_order
from .sign_correction import rotation_verdicts
from .generators import random_rotation
from .verdicts import sparse_verdict
from .shape_matching import trace_verdict
from . import reference
from starter import shapes

#: Relative tolerance of quantities computed without a solve (weights, matrices, energies).
DIRECT_RTOL = 1e-9
#: Handles are copied, not solved for: ``|U[handles] - handle_positions|`` up to this times the coordinates' size.
HANDLE_TOL = 1e-12
#: A global step's solution against the reference's, relative to the bounding-box diagonal.
SOLVE_RTOL = 1e-8
#: ``arap_solve`` after several iterations (energies relative, positions relative to the bounding-box diagonal).
ITERATE_RTOL = 1e-6


def _turn(P: np.ndarray, R: np.ndarray, pivot: np.ndarray) -> np.ndarray:
    return (P - pivot) @ R.T + pivot


def axis_rotation(axis: int, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    i, j = [k for k in range(3) if k != axis]
    R = np.eye(3)
    R[[i, i, j, j], [i, j, i, j]] = [c, -s, s, c]
    return R


DISC = "2D disc with two holes, clockwise triangles, random handles dragged"
JITTERED = "2D jittered grid with obtuse triangles, each in either orientation, random handles dragged"
TWO_COMPONENTS = "two 2D components, one clockwise and one counter-clockwise, handles on each"
SCALED = "2D strip turned by 90°, the whole problem scaled by 1/100, rotated and moved 20 units away"


def deformation_scenes(rng: np.random.Generator) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """Hidden ARAP problems by label: ``(V, F, handles, handle_positions)``, vertices in random order.

    Covers 2D and 3D, closed and bounded meshes, thin and obtuse triangles,
    a planar mesh in 3D, two connected components, large rotations of the
    handles and handles in random order; clockwise, counter-clockwise and
    mixed 2D triangles; a whole problem scaled down and moved far away.
    """
    scenes = {}

    def add(label, V, F, handles, move):
        V, F = relabel(V, F, rng)
        handles = unsorted_order(rng, handles(V))
        scenes[label] = (V, F, handles, move(V[handles]))

    def ends(V):
        return np.flatnonzero((V[:, 0] == V[:, 0].min()) | (V[:, 0] == V[:, 0].max()))

    def random_vertices(k):
        return lambda V: rng.choice(len(V), k, replace=False)

    def drag(P):
        return P + rng.normal(0.0, 0.3, P.shape)

    def bend_right_end(angle):
        def move(P):
            right = P[:, 0] == P[:, 0].max()
            pivot = P[right].mean(axis=0)
            R = random_rotation(rng, 2, angle) if P.shape[1] == 2 else axis_rotation(1, angle)
            out = P.copy()
            out[right] = _turn(P[right], R, pivot) + 0.5 * np.eye(P.shape[1])[-1]
            return out

        return move

    def twist(P):
        right = P[:, 0] == P[:, 0].max()
        out = P.copy()
        out[right] = _turn(P[right], axis_rotation(0, rng.uniform(2.0, 2.8)), P[right].mean(axis=0))
        return out

    add("2D strip, right end turned by 90°", *shapes.grid_2d(10, 3, width=3.0, height=0.6), ends, bend_right_end(np.pi / 2))
    V, F = shapes.disc_with_holes(2, 0.04)
    add(DISC, V, clockwise(F), random_vertices(4), drag)
    add(
        "2D strip of thin triangles (aspect 100:1), right end turned",
        *shapes.grid_2d(10, 2, width=1.0, height=0.002),
        ends,
        bend_right_end(0.6),
    )
    V, F = jittered_grid(rng, 7, 7, amount=0.35)
    add(JITTERED, V, mixed_orientation(F, rng), random_vertices(5), drag)
    add("3D bar bent by 90°", *shapes.bar(length=3.0, nx=9, ny=2, nz=2), ends, bend_right_end(np.pi / 2))
    add("3D bar twisted by more than 110°", *shapes.bar(length=3.0, nx=8, ny=2, nz=2), ends, twist)
    V, F = shapes.grid_2d(6, 4, width=1.5)
    add(
        "planar 3D mesh (z = 0), random handles lifted out of the plane",
        np.c_[V, np.zeros(len(V))],
        F,
        random_vertices(4),
        lambda P: P + rng.normal(0.0, 0.3, P.shape) * [1.0, 1.0, 2.0],
    )
    grid = shapes.grid_2d(5, 3)
    add(
        TWO_COMPONENTS,
        *disjoint_union(grid, (grid[0] + [2.0, 0.0], clockwise(grid[1]))),
        lambda V: np.concatenate([rng.choice(np.flatnonzero(V[:, 0] < 1.5), 2, replace=False), rng.choice(np.flatnonzero(V[:, 0] > 1.5), 2, replace=False)]),
        drag,
    )
    # The strip's problem again, 100 times smaller, turned and 20 units from the origin: nothing may depend on the size or place.
    V, F, handles, P = scenes["2D strip, right end turned by 90°"]
    move = similar_copy(rng, 2, 0.01, 20.0)
    scenes[SCALED] = (move(V), F, handles, move(P))
    return scenes


def _cotangent_meshes(rng: np.random.Generator) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Meshes for the weight and Laplacian checks (no handles needed)."""
    meshes = {label: (V, F) for label, (V, F, _, _) in deformation_scenes(rng).items() if "twisted" not in label}
    meshes["3D torus"] = relabel(*shapes.torus(n_major=10, n_minor=6), rng)
    return meshes


def _deformed(rng: np.random.Generator, V: np.ndarray, kind: str) -> np.ndarray:
    """Deformed positions ``U`` of ``V``: a noisy rotation, a mirror image, or a collapse onto a line."""
    d = V.shape[1]
    if kind == "rotated":
        return V @ random_rotation(rng, d).T + rng.normal(0.0, 0.05, V.shape) + rng.normal(size=d)
    if kind == "mirrored":
        return (V * np.r_[-1.0, np.ones(d - 1)]) @ random_rotation(rng, d).T + rng.normal(0.0, 0.02, V.shape)
    if kind == "collapsed":
        return np.outer(V @ rng.normal(size=d), rng.normal(size=d))
    raise ValueError(f"unknown deformation {kind!r}")


def _local_step_inputs(rng: np.random.Generator) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """``(label, V, U, F, C)`` for the covariance, rotation and energy checks.

    ``C`` is the true half-cotangent matrix of ``V`` (from libigl) in most
    cases and arbitrary signed weights in one, so that an implementation
    recomputing its own weights instead of using ``C`` fails.
    """
    import igl

    scenes = deformation_scenes(rng)
    picks = [
        ("2D disc with two holes, clockwise", DISC, "rotated"),
        ("2D jittered grid, triangles in either orientation", JITTERED, "mirrored"),
        ("3D bar", "3D bar bent by 90°", "rotated"),
        ("3D bar", "3D bar twisted by more than 110°", "mirrored"),
        ("planar 3D mesh (z = 0)", "planar 3D mesh (z = 0), random handles lifted out of the plane", "mirrored"),
        ("2D strip", "2D strip, right end turned by 90°", "collapsed"),
    ]
    out = []
    for name, scene, kind in picks:
        V, F = scenes[scene][:2]
        out.append((f"{name}, {kind} copy", V, _deformed(rng, V, kind), F, igl.cotmatrix_entries(V, F)))
    V, F = scenes[TWO_COMPONENTS][:2]
    out.append(("two 2D components of opposite orientations, arbitrary signed weights C", V, _deformed(rng, V, "rotated"), F, rng.normal(size=F.shape)))
    return out


def energy_scale(V: np.ndarray, U: np.ndarray, F: np.ndarray, C: np.ndarray) -> float:
    """``3 Σ |C| (‖e‖² + ‖e'‖²)``: bounds the terms of the ARAP energy, for roundoff tolerances."""
    edge = lambda X: X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]  # noqa: E731 - edge opposite each corner
    return 3.0 * float(np.sum(np.abs(C) * (np.sum(edge(V) ** 2, -1) + np.sum(edge(U) ** 2, -1))))


def energy_verdict(name: str, found, best, scale: float, rtol: float, at_most: bool = False) -> Verdict:
    """Energies ``found`` equal (or with ``at_most``, do not exceed) ``best`` within ``rtol`` plus roundoff of the terms.

    ``found`` and ``best`` are floats or equally long 1-D arrays (one energy per iteration).
    """
    found, best = np.atleast_1d(np.asarray(found, float)), np.atleast_1d(np.asarray(best, float))
    excess = found - best if at_most else np.abs(found - best)
    bad = np.flatnonzero(excess > rtol * np.abs(best) + 1e-12 * scale)
    detail = ""
    if bad.size:
        k = bad[0]
        where = f"energies[{k}] = " if len(found) > 1 else ""
        detail = f"{where}{found[k]:.12g}, expected {'at most ' if at_most else ''}{best[k]:.12g}"
    return verdict(name, bad.size == 0, detail)


def _bbox_diagonal(V: np.ndarray) -> float:
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def handle_verdict(U: np.ndarray, handles: np.ndarray, positions: np.ndarray) -> Verdict:
    err = np.abs(U[handles] - positions).max(axis=1)
    worst = int(np.argmax(err))
    return verdict(
        "handles met exactly",
        err[worst] <= HANDLE_TOL * max(1.0, float(np.abs(positions).max())),
        f"U[{handles[worst]}] is {U[handles[worst]].tolist()}, its handle position is {positions[worst].tolist()} "
        f"(difference {err[worst]:.3g})",
    )


def positions_verdict(name: str, U: np.ndarray, want: np.ndarray, V: np.ndarray, rtol: float) -> Verdict:
    ok, where = close(U, want, rtol, scale=_bbox_diagonal(V))
    return verdict(name, ok, f"{where} (vertex, coordinate)")


class CotangentWeightsChecks(FunctionChecks):
    function = "cotangent_weights"
    description = "C[t, k] = ½ cot of the angle at corner k, in 2D and 3D, with thin and obtuse, clockwise and counter-clockwise triangles"

    def cases(self, rng):
        return [Case.call(label, "cotangent_weights", V, F) for label, (V, F) in _cotangent_meshes(rng).items()]

    def verify(self, case, got, expected):
        F = case.args()[1]
        C = as_array(got, F.shape, "C")
        want = as_array(expected, F.shape, "the reference's C")
        scale = float(np.abs(want).max())
        ok, where = close(C, want, DIRECT_RTOL, scale)
        hint = ""
        if not ok:
            if close(C, 2.0 * want, DIRECT_RTOL, scale)[0]:
                hint = " (these are cot, the contract asks for ½ cot)"
            elif any(close(C, np.roll(want, s, axis=1), DIRECT_RTOL, scale)[0] for s in (1, 2)):
                hint = " (columns are shifted: C[t, k] belongs to the angle at corner k, opposite edge (F[t,k+1], F[t,k+2]))"
            elif close(np.abs(C), np.abs(want), DIRECT_RTOL, scale)[0]:
                hint = " (some triangles have the sign wrong: clockwise triangles? sin is |u × v| / (|u| |v|), never negative)"
        return [verdict("C matches ½ cot of each corner's angle", ok, f"{where} (triangle, corner){hint}")]


class CotangentLaplacianChecks(FunctionChecks):
    function = "cotangent_laplacian"
    description = "sparse symmetric L with L_ij = Σ C over the edges (i, j) and zero row sums, equal to igl.cotmatrix"

    def cases(self, rng):
        return [Case.call(label, "cotangent_laplacian", V, F) for label, (V, F) in _cotangent_meshes(rng).items()]

    def verify(self, case, got, expected):
        n = len(case.args()[0])
        L = as_matrix(got, (n, n), "L")
        want = as_matrix(expected, (n, n), "the reference's L")
        scale = max_abs(want)
        ok, where = close(L, want, DIRECT_RTOL, scale)
        hint = ""
        if not ok and close(L, -want, DIRECT_RTOL, scale)[0]:
            import igl

            V, F = case.args()
            clockwise = V.shape[1] == 2 and bool(np.all(igl.doublearea(V, F) < 0))  # signed for 2D input
            hint = (
                " (the signs are flipped on this clockwise mesh: are the cotangents divided by a signed area?)"
                if clockwise
                else " (the signs are flipped: off-diagonal entries are +Σ C, the diagonal is minus their sum)"
            )
        return [
            sparse_verdict(got),
            verdict("L matches", ok, f"{where}{hint}"),
        ]


class ArapCovariancesChecks(FunctionChecks):
    function = "arap_covariances"
    description = "S_i = Σ C e e'ᵀ over the triangles around each vertex, with the given C, in 2D and 3D"

    def cases(self, rng):
        return [Case.call(label, "arap_covariances", V, U, F, C) for label, V, U, F, C in _local_step_inputs(rng)]

    def verify(self, case, got, expected):
        V = case.args()[0]
        n, d = V.shape
        S = as_array(got, (n, d, d), "S")
        want = as_array(expected, (n, d, d), "the reference's S")
        scale = float(np.abs(want).max())
        ok, where = close(S, want, DIRECT_RTOL, scale)
        hint = " (each S_i is transposed: rest edges on the left, e e'ᵀ)" if (
            not ok and close(S, np.swapaxes(want, 1, 2), DIRECT_RTOL, scale)[0]
        ) else ""
        return [verdict("S matches", ok, f"{where} (vertex, row, column){hint}")]


class ArapRotationsChecks(FunctionChecks):
    function = "arap_rotations"
    description = "each R_i a rotation maximizing tr(R_i S_i), including mirrored, planar and collapsed neighbourhoods"

    def cases(self, rng):
        return [Case.call(label, "arap_rotations", V, U, F, C) for label, V, U, F, C in _local_step_inputs(rng)]

    def verify(self, case, got, expected):
        V, U, F, C = case.args()
        n, d = V.shape
        R = as_array(got, (n, d, d), "R")
        R_ref = as_array(expected, (n, d, d), "the reference's R")
        S = np.asarray(reference("arap_covariances")(V, U, F, C))
        best = np.einsum("kij,kji->k", R_ref, S)
        return rotation_verdicts(R) + [trace_verdict(R, S, best, "optimal tr(R_i S_i) at every vertex")]


class ArapEnergyChecks(FunctionChecks):
    function = "arap_energy"
    description = "Σ_i Σ_{t ∋ i} Σ_k C ‖e' − R_i e‖², with given rotations, zero for a rigid motion"

    def cases(self, rng):
        inputs = _local_step_inputs(rng)
        _, V, _, F, C = inputs[2]
        # A rigid motion with its own rotation at every vertex costs nothing.
        Rg = random_rotation(rng, 3)
        rigid = (V @ Rg.T + rng.normal(size=3), np.tile(Rg, (len(V), 1, 1)))
        cases = [Case.call("3D bar, rigid motion with its rotation at every vertex", "arap_energy", V, rigid[0], F, C, rigid[1])]
        for i, (label, V, U, F, C) in enumerate(inputs):
            d = V.shape[1]
            if i % 2:
                cases.append(Case.call(f"{label}, every R_i = I", "arap_energy", V, U, F, C, np.tile(np.eye(d), (len(V), 1, 1))))
            else:
                R = np.stack([random_rotation(rng, d) for _ in V])
                cases.append(Case.call(f"{label}, random rotations", "arap_energy", V, U, F, C, R))
        return cases

    def verify(self, case, got, expected):
        V, U, F, C, _ = case.args()
        return [energy_verdict("energy", as_float(got, "energy"), float(expected), energy_scale(V, U, F, C), DIRECT_RTOL)]


def _random_local_rotations(rng: np.random.Generator, V: np.ndarray, F: np.ndarray, P: np.ndarray, handles: np.ndarray) -> np.ndarray:
    """Rotations of a realistic local step: the optimal rotations of ``V`` with its handles moved to ``P``."""
    import igl

    U = V.copy()
    U[handles] = P
    R = np.asarray(reference("arap_rotations")(V, U, F, igl.cotmatrix_entries(V, F)))
    # Some cells get random rotations instead, so the target is not near any ARAP iterate.
    mix = rng.uniform(size=len(V)) < 0.3
    R[mix] = np.stack([random_rotation(rng, V.shape[1]) for _ in range(int(mix.sum()))]).reshape(-1, *R.shape[1:])
    return R


def _global_step_verdicts(U_got, U_ref, V, F, R, handles, positions) -> list[Verdict]:
    """Handles, energy of ``U_got`` for ``R`` against the reference's minimum, and ``U_got`` against ``U_ref``."""
    n, d = V.shape
    U = as_array(U_got, (n, d), "U")
    U_ref = as_array(U_ref, (n, d), "the reference's U")
    C = np.asarray(reference("cotangent_weights")(V, F))
    energy = reference("arap_energy")
    return [
        handle_verdict(U, handles, positions),
        energy_verdict(
            "minimal energy for the given rotations",
            float(energy(V, U, F, C, R)),
            float(energy(V, U_ref, F, C, R)),
            energy_scale(V, U_ref, F, C),
            DIRECT_RTOL,
            at_most=True,
        ),
        positions_verdict("U is the unique minimizer", U, U_ref, V, SOLVE_RTOL),
    ]


class ArapPrecomputeChecks(FunctionChecks):
    function = "arap_precompute"
    needs = ("arap_global_step", "arap_solve")
    description = "the precomputed data serves several global steps and solves in a row, handles in any order"

    def cases(self, rng):
        scenes = deformation_scenes(rng)
        cases = []
        for label in (DISC, "3D bar bent by 90°", TWO_COMPONENTS):
            V, F, handles, P = scenes[label]
            P2 = P + rng.normal(0.0, 0.2, P.shape)
            R1, R2 = (_random_local_rotations(rng, V, F, X, handles) for X in (P, P2))
            steps = [Step("arap_precompute", (V, F, handles)), Step("arap_global_step", (Ref(0), R1, P)), Step("arap_global_step", (Ref(0), R2, P2))]
            cases.append(Case(f"{label}: two global steps with one precomputation", steps, {"R": R2, "P": P2}))
        V, F, handles, P = scenes["2D strip, right end turned by 90°"]
        R = _random_local_rotations(rng, V, F, P, handles)
        steps = [Step("arap_precompute", (V, F, handles)), Step("arap_solve", (Ref(0), P), {"iterations": 2}), Step("arap_global_step", (Ref(0), R, P))]
        cases.append(Case("2D strip: a global step after a solve with the same precomputation", steps, {"R": R, "P": P}))
        return cases

    def verify(self, case, got, expected):
        V, F, handles = case.args(0)
        return _global_step_verdicts(got, expected, V, F, case.context["R"], handles, case.context["P"])


class ArapGlobalStepChecks(FunctionChecks):
    function = "arap_global_step"
    needs = ("arap_precompute",)
    description = "U minimizing the ARAP energy for given rotations with the handles met exactly, in 2D and 3D, handles in any order, at any size and place"

    def cases(self, rng):
        cases = []
        for label, (V, F, handles, P) in deformation_scenes(rng).items():
            R = _random_local_rotations(rng, V, F, P, handles)
            cases.append(Case(label, [Step("arap_precompute", (V, F, handles)), Step("arap_global_step", (Ref(0), R, P))]))
        return cases

    def verify(self, case, got, expected):
        V, F, handles = case.args(0)
        _, R, P = case.args(1)
        return _global_step_verdicts(got, expected, V, F, R, handles, P)


def _start(V: np.ndarray, U0: np.ndarray | None, handles: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """The first iterate of ``arap_solve``: ``U0`` (``V`` if None) with the handle rows replaced."""
    U = (V if U0 is None else U0).copy()
    U[handles] = positions
    return U


def local_global_energy_verdicts(energies, energies_ref, iterations: int, last_with_rotations: float, fresh: float, scale: float, unknown: str) -> list[Verdict]:
    """Verdicts on the energies a local–global solve returns (ARAP's, FAST's).

    Parameters
    ----------
    energies, energies_ref : (k,) numpy.ndarray
        The student's and the reference's energies from the same start.
    iterations : int
        Iterations asked for; the comparisons need ``len(energies) == iterations``.
    last_with_rotations : float
        Energy of the student's result with the last iteration's rotations (what ``energies[-1]`` must be).
    fresh : float
        Energy of the student's result with fresh optimal rotations (a lower bound for ``energies[-1]``).
    scale : float
        Size of the energy's terms, for roundoff.
    unknown : str
        The solved-for quantity in messages (``"U"``, ``"T"``).
    """
    rises = np.flatnonzero(np.diff(energies) > DIRECT_RTOL * np.abs(energies[:-1]) + 1e-12 * scale)
    detail = ""
    if rises.size:
        k = rises[0]
        detail = f"energies[{k + 1}] = {energies[k + 1]:.12g} > energies[{k}] = {energies[k]:.12g}"
    verdicts = [verdict("energies non-increasing", rises.size == 0, detail)]
    if len(energies) == iterations:
        verdicts += [
            energy_verdict("energies match the reference's from the same start", energies, energies_ref, scale, ITERATE_RTOL),
            energy_verdict(f"last energy is of {unknown} with the last iteration's rotations", float(energies[-1]), last_with_rotations, scale, ITERATE_RTOL),
            verdict(
                f"last energy not below the energy of {unknown} with fresh optimal rotations",
                energies[-1] >= fresh - ITERATE_RTOL * fresh - 1e-12 * scale,
                f"energies[-1] = {energies[-1]:.12g}, but no rotations give {unknown} an energy below {fresh:.12g}",
            ),
        ]
    return verdicts


class ArapSolveChecks(FunctionChecks):
    function = "arap_solve"
    needs = ("arap_precompute",)
    description = "(U, energies): one energy per iteration, non-increasing, of U with the step's rotations; U as the reference's"

    def cases(self, rng):
        scenes = deformation_scenes(rng)
        plans = [
            ("2D strip, right end turned by 90°", None, 8),
            (DISC, "noisy", 3),
            ("2D strip of thin triangles (aspect 100:1), right end turned", None, 4),
            ("3D bar bent by 90°", None, 6),
            ("3D bar twisted by more than 110°", "noisy", 1),
            ("planar 3D mesh (z = 0), random handles lifted out of the plane", None, None),
            (TWO_COMPONENTS, "rotated", 5),
            (SCALED, None, 3),
        ]
        cases = []
        for label, start, iterations in plans:
            V, F, handles, P = scenes[label]
            kwargs = {} if iterations is None else {"iterations": iterations}
            if start == "noisy":
                kwargs["U0"] = V + rng.normal(0.0, 0.05, V.shape)
            elif start == "rotated":
                kwargs["U0"] = V @ random_rotation(rng, V.shape[1]).T
            detail = f"{iterations or 'default 10'} iteration(s) from {start + ' U0' if start else 'V'}"
            cases.append(Case(f"{label}, {detail}", [Step("arap_precompute", (V, F, handles)), Step("arap_solve", (Ref(0), P), kwargs)]))
        return cases

    def verify(self, case, got, expected):
        V, F, handles = case.args(0)
        _, P = case.args(1)
        kwargs = case.steps[1].kwargs
        iterations = kwargs.get("iterations", 10)
        n, d = V.shape
        U_got, energies_got = as_pair(got, "(U, energies)")
        U = as_array(U_got, (n, d), "U")
        if isinstance(energies_got, tuple):  # a list of numpy scalars travels as a sequence of 0-d arrays
            energies_got = [as_float(e, f"energies[{k}]") for k, e in enumerate(energies_got)]
        energies = as_array(energies_got, (None,), "energies")
        U_ref, energies_ref = (as_array(x) for x in as_pair(expected, "the reference's (U, energies)"))
        C = np.asarray(reference("cotangent_weights")(V, F))
        energy = reference("arap_energy")
        scale = energy_scale(V, U_ref, F, C)
        # The rotations of the last iteration are the local step on the previous iterate.
        if iterations == 1:
            previous = _start(V, kwargs.get("U0"), handles, P)
        else:
            data = reference("arap_precompute")(V, F, handles)
            previous = np.asarray(reference("arap_solve")(data, P, U0=kwargs.get("U0"), iterations=iterations - 1)[0])
        R_last = reference("arap_rotations")(V, previous, F, C)
        fresh = float(energy(V, U, F, C, reference("arap_rotations")(V, U, F, C)))

        verdicts = [
            verdict("len(energies) == iterations", len(energies) == iterations, f"{len(energies)} energies for {iterations} iterations"),
            handle_verdict(U, handles, P),
        ]
        verdicts += local_global_energy_verdicts(energies, energies_ref, iterations, float(energy(V, U, F, C, R_last)), fresh, scale, "U")
        verdicts.append(positions_verdict("U matches the reference's from the same start", U, U_ref, V, ITERATE_RTOL))
        return verdicts


class LaplacianEditingChecks(FunctionChecks):
    function = "laplacian_editing"
    description = "the global step with every R_i = I: handles met exactly, U as the reference's"

    def cases(self, rng):
        return [Case.call(label, "laplacian_editing", V, F, handles, P) for label, (V, F, handles, P) in deformation_scenes(rng).items()]

    def verify(self, case, got, expected):
        V, F, handles, P = case.args()
        R = np.tile(np.eye(V.shape[1]), (len(V), 1, 1))
        return _global_step_verdicts(got, expected, V, F, R, handles, P)
