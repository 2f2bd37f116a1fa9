"""Checks of stage 02b, k-harmonic displacement deformation (the linear baseline of ARAP).

``Q_k`` has a unique answer and is compared with the reference's. A solve is
judged by what defines it: the handles' displacements met exactly, the free
rows of ``Q D`` zero (the energy is stationary there), and ``D`` the reference's
(the minimizer is unique once every component holds a handle). Inputs travel
dense (the kernel's wire sends arrays), as the contract allows.
"""

from __future__ import annotations

import igl
import numpy as np

from grader.checks.base import Case, FunctionChecks, Ref, Step, as_array, as_matrix, close, max_abs, raises, verdict
from starter import shapes

from . import reference
from .generators import bad_handle_sets, disjoint_union, jittered_grid, random_rotation, relabel, unsorted_order
from .verdicts import sparse_verdict

#: Relative tolerance of ``Q_k`` (products of sparse matrices: rounding only).
MATRIX_RTOL = 1e-9
#: Handles are copied, not solved for.
HANDLE_TOL = 1e-12
#: ``(Q D)_f`` relative to ``|Q| |D|``, and ``D`` against the reference's relative to the largest displacement.
SOLVE_RTOL = 1e-8


def _operators(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``L`` (cotangent matrix) and ``M`` (Voronoi lumped mass), dense, as the notebook's provided cell builds them."""
    L = igl.cotmatrix(V, F)
    M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
    return L.toarray(), M.toarray()


def _ends(V: np.ndarray, axis: int = 0) -> tuple[np.ndarray, np.ndarray]:
    lo, hi = V[:, axis].min(), V[:, axis].max()
    span = hi - lo
    return np.flatnonzero(V[:, axis] <= lo + 1e-9 * span), np.flatnonzero(V[:, axis] >= hi - 1e-9 * span)


def k_harmonic_scenes(rng: np.random.Generator) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """label -> ``(V, F, handles, handle_displacements)``: region handles as in libigl's tutorials 401/402."""
    scenes = {}
    V, F = relabel(*jittered_grid(rng, 12, 5, width=3.0, height=1.0), rng)
    left, right = _ends(V)
    handles = np.r_[left, right]
    D = np.zeros((len(handles), 2))
    D[len(left):] = [0.4, 0.9]
    scenes["2D strip, left end fixed, right end lifted"] = (V, F, handles, D)

    V, F = shapes.bar(length=4.0, width=1.0, height=1.0, nx=10, ny=3, nz=3)
    V, F = relabel(V, F, rng)
    left, right = _ends(V)
    handles = unsorted_order(rng, np.r_[left, right])
    R = random_rotation(rng, 3, angle=np.pi / 2)
    centre = V[right].mean(axis=0)
    moved = (V[handles] - centre) @ R.T + centre + [0.0, 0.5, 0.0]
    D = np.where(np.isin(handles, right)[:, None], moved - V[handles], 0.0)
    scenes["3D bar, one end fixed, the other turned by 90° and moved (handles in any order)"] = (V, F, handles, D)

    (Va, Fa), (Vb, Fb) = jittered_grid(rng, 6, 4), jittered_grid(rng, 5, 5)
    V, F = disjoint_union((Va, Fa), (Vb + [3.0, 0.0], Fb))
    first, second = np.flatnonzero(V[:, 0] <= 0.0), np.flatnonzero(V[:, 0] >= 4.0 - 1e-12)
    handles = np.r_[first, second]
    D = rng.normal(0.0, 0.3, (len(handles), 2))
    scenes["two components, each with a handle region, random displacements"] = (V, F, handles, D)

    V, F = relabel(*jittered_grid(rng, 8, 8), rng)
    handles = rng.choice(len(V), 5, replace=False)
    D = rng.normal(0.0, 0.2, (5, 2))
    scenes["2D square, five single-vertex handles"] = (V, F, handles, D)
    return scenes


def exact_problems(rng: np.random.Generator) -> list[tuple]:
    """``(label, (V, F), Q_k, handles, D_h, D, property)``: problems whose answer ``D`` is known exactly.

    Constants cost no energy, so a common translation of every handle moves every
    vertex by it (any mesh, any k). On a flat mesh ``L`` annihilates affine
    functions away from the boundary, so with the outer ``k`` rings of a grid as
    handles the free rows of ``Q_k`` do too: an affine displacement is reproduced.
    """
    out = []
    V, F = relabel(*shapes.bar(length=3.0, width=1.0, height=1.0, nx=8, ny=2, nz=2), rng)
    handles = unsorted_order(rng, np.r_[_ends(V)])
    t = rng.normal(size=3)
    L, M = _operators(V, F)
    for k in (1, 2):
        out.append((f"3D bar, both ends moved by the same translation, k = {k}", (V, F), reference("k_harmonic_operator")(L, M, k).toarray(),
                    handles, np.tile(t, (len(handles), 1)), np.tile(t, (len(V), 1)), "every vertex moves by the handles' translation"))
    nx, ny = 9, 7
    V, F = relabel(*shapes.grid_2d(nx, ny, width=1.8, height=1.4), rng)
    i, j = np.rint(V[:, 0] / 0.2), np.rint(V[:, 1] / 0.2)
    ring = np.minimum.reduce([i, nx - i, j, ny - j])  # 0 on the boundary, 1 on the next ring...
    L, M = _operators(V, F)
    for k in (1, 2):
        handles = unsorted_order(rng, np.flatnonzero(ring < k))
        A, b = rng.normal(size=(2, 2)), rng.normal(size=2)
        D = V @ A.T + b
        out.append((f"flat 2D grid, its outer {k} ring(s) of vertices moved by a random affine map, k = {k}", (V, F),
                    reference("k_harmonic_operator")(L, M, k).toarray(), handles, D[handles], D, "the affine displacement is reproduced exactly"))
    return out


def _solve_cases(rng: np.random.Generator) -> list[tuple[str, tuple, np.ndarray, np.ndarray, np.ndarray, int]]:
    """``(label, (V, F), Q_k, handles, D_h, k)`` for k = 1 and 2 on every scene, and k = 3 on one."""
    out = []
    for label, (V, F, handles, D) in k_harmonic_scenes(rng).items():
        L, M = _operators(V, F)
        for k in (1, 2) if "single-vertex" not in label else (2, 3):
            Q = reference("k_harmonic_operator")(L, M, k).toarray()
            out.append((f"{label}, k = {k}", (V, F), Q, handles, D, k))
    return out


def _solve_verdicts(got, expected, Q: np.ndarray, handles: np.ndarray, D_h: np.ndarray) -> list:
    n, d = len(Q), D_h.shape[1]
    D = as_array(got, (n, d), "D")
    want = as_array(expected, (n, d), "the reference's D")
    err = np.abs(D[handles] - D_h).max(axis=1)
    worst = int(np.argmax(err))
    free = np.setdiff1d(np.arange(n), handles)
    residual = (Q @ D)[free]
    scale = float(np.abs(Q).max()) * max(float(np.abs(want).max()), 1e-12)
    r_worst = np.unravel_index(int(np.argmax(np.abs(residual))), residual.shape) if residual.size else (0, 0)
    r_value = float(np.abs(residual[r_worst])) if residual.size else 0.0
    hint = ""
    if np.abs(D[free]).max(initial=0.0) == 0.0 and np.abs(want[free]).max(initial=0.0) > 0.0:
        hint = " (every free vertex stays put: the handles' columns Q_fh D_h belong on the right-hand side)"
    elif close(D[free], -want[free], SOLVE_RTOL, float(np.abs(want).max()))[0]:
        hint = " (the free part has the wrong sign: Q_ff D_f = -Q_fh D_h)"
    ok, where = close(D, want, SOLVE_RTOL, float(np.abs(want).max()))
    return [
        verdict("handles' displacements met exactly", err[worst] <= HANDLE_TOL * max(1.0, float(np.abs(D_h).max())),
                f"D[{handles[worst]}] is {D[handles[worst]].tolist()}, its handle's displacement is {D_h[worst].tolist()}"),
        verdict("(Q D)[free] = 0: the energy is stationary at every free vertex", r_value <= SOLVE_RTOL * max(scale, 1.0),
                f"(Q D)[{int(free[r_worst[0]])}, {int(r_worst[1])}] = {r_value:.3g}{hint}"),
        verdict("D is the unique minimizer", ok, f"{where} (vertex, coordinate){hint}"),
    ]


class KHarmonicOperatorChecks(FunctionChecks):
    function = "k_harmonic_operator"
    description = "sparse Q_k = (-L)(M⁻¹(-L))^(k-1) for k = 1, 2, 3 in 2D and 3D; k < 1 raises ValueError"

    def cases(self, rng):
        cases = []
        scenes = k_harmonic_scenes(rng)
        for (label, (V, F, _, _)), ks in zip(scenes.items(), ((1, 2), (2, 3), (1,), (2,))):
            L, M = _operators(V, F)
            for k in ks:
                cases.append(Case.call(f"{label.split(',')[0]}, k = {k}", "k_harmonic_operator", L, M, k))
        V, F, _, _ = next(iter(scenes.values()))
        L, M = _operators(V, F)
        cases.append(raises("k = 0", [Step("k_harmonic_operator", (L, M, 0))]))
        return cases

    def verify(self, case, got, expected):
        L, _, k = case.args()
        n = len(L)
        Q = as_matrix(got, (n, n), "Q")
        want = as_matrix(expected, (n, n), "the reference's Q")
        scale = max_abs(want)
        ok, where = close(Q, want, MATRIX_RTOL, scale)
        hint = ""
        if not ok:
            Ld = -np.asarray(L)
            if close(Q, -want, MATRIX_RTOL, scale)[0]:
                hint = " (the sign: Q_k is positive semidefinite, built from -L; L itself is negative semidefinite)"
            elif k >= 2 and close(Q, np.linalg.matrix_power(Ld, k), MATRIX_RTOL, scale)[0]:
                hint = " (M⁻¹ is missing between the factors: Q_2 = (-L) M⁻¹ (-L))"
            elif any(close(Q, reference("k_harmonic_operator")(L, case.args()[1], j), MATRIX_RTOL, scale)[0] for j in (k - 1, k + 1) if j >= 1):
                hint = " (k is off by one: Q_1 = -L has one factor, Q_k has k)"
        return [sparse_verdict(got), verdict("Q matches (-L)(M⁻¹(-L))^(k-1)", ok, f"{where}{hint}")]


class KHarmonicPrecomputeChecks(FunctionChecks):
    function = "k_harmonic_precompute"
    needs = ("k_harmonic_solve",)
    description = "the precomputed data serves two solves in a row, handles in any order; bad handles raise ValueError"

    def cases(self, rng):
        cases, solves = [], _solve_cases(rng)
        for label, _, Q, handles, D_h, _ in solves[::2]:
            D2 = rng.normal(0.0, 0.3, D_h.shape)
            steps = [Step("k_harmonic_precompute", (Q, handles)), Step("k_harmonic_solve", (Ref(0), D_h)),
                     Step("k_harmonic_solve", (Ref(0), D2))]
            cases.append(Case(f"{label}: two solves with one precomputation", steps, {"D_h": D2}))
        _, _, Q, handles, _, _ = solves[0]
        for what, bad in bad_handle_sets(handles, len(Q)):
            cases.append(raises(f"the 2D strip with {what}", [Step("k_harmonic_precompute", (Q, bad))]))
        return cases

    def verify(self, case, got, expected):
        Q, handles = case.args(0)
        return _solve_verdicts(got, expected, np.asarray(Q), np.asarray(handles), case.context["D_h"])


class KHarmonicSolveChecks(FunctionChecks):
    function = "k_harmonic_solve"
    needs = ("k_harmonic_precompute",)
    description = (
        "D with the handles' displacements exactly and (Q D)[free] = 0, for k = 1, 2, 3, in 2D and 3D, two components; "
        "translations reproduced exactly, affine maps on flat grids with k rings of handles too"
    )

    def cases(self, rng):
        # the mesh stays here (the kernel gets Q): the feedback picture draws V + D on it
        cases = [
            Case(label, [Step("k_harmonic_precompute", (Q, handles)), Step("k_harmonic_solve", (Ref(0), D_h))], {"mesh": mesh})
            for label, mesh, Q, handles, D_h, _ in _solve_cases(rng)
        ]
        for label, mesh, Q, handles, D_h, D, what in exact_problems(rng):
            cases.append(Case(label, [Step("k_harmonic_precompute", (Q, handles)), Step("k_harmonic_solve", (Ref(0), D_h))],
                              {"mesh": mesh, "exact": D, "property": what}))
        return cases

    def verify(self, case, got, expected):
        Q, handles = case.args(0)
        _, D_h = case.args(1)
        verdicts = _solve_verdicts(got, expected, np.asarray(Q), np.asarray(handles), np.asarray(D_h))
        if "exact" in case.context:  # a problem whose answer is known in closed form, not only the reference's
            D = as_array(got, case.context["exact"].shape, "D")
            ok, where = close(D, case.context["exact"], SOLVE_RTOL, float(np.abs(D_h).max()))
            verdicts.insert(2, verdict(case.context["property"], ok, f"{where} (vertex, coordinate)"))
        return verdicts
