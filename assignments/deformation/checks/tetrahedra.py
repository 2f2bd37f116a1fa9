"""Checks of stage 07, tetrahedra (``LECTURE_CONTRACT.md``): finite elements and ARAP with tetrahedral cells.

Cases use the course meshes ``hand_tet`` and ``bar_tet`` with their vertices and
tetrahedra in random order and their positions jittered, plus single
tetrahedra of both orientations, so neither the grid's right angles nor a
fixed corner order can hide a mistake.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from grader.checks.base import (
    Case,
    FunctionChecks,
    Ref,
    Step,
    as_array,
    as_float,
    as_matrix,
    close,
    max_abs,
    once_per_case,
    raises,
    verdict,
)
from .generators import bad_handle_sets, random_rotation
from starter.meshes import load_mesh

#: Relative tolerance of the direct formulas (one 3x3 inverse per tetrahedron).
TET_RTOL = 1e-9
#: Largest ‖RᵀR − I‖ accepted for a rotation, and the slack on ‖J − R‖ optimality.
ROTATION_TOL = 1e-8


def _shuffled(name: str, rng: np.random.Generator, jitter: float = 0.15, flip: bool = False):
    """A course tet mesh, vertices and tetrahedra in random order, jittered by ``jitter`` of the grid step.

    With ``flip`` a random half of the tetrahedra swap two corners (negative orientation).
    """
    V, T = load_mesh(name)
    step = float(np.linalg.norm(V[T[0, 1]] - V[T[0, 0]]))
    V = V + jitter * step * rng.uniform(-1, 1, V.shape) / np.sqrt(3)
    order = rng.permutation(len(V))
    new_index = np.empty_like(order)
    new_index[order] = np.arange(len(V))
    T = new_index[T][rng.permutation(len(T))]
    if flip:
        swap = rng.random(len(T)) < 0.5
        T[swap] = T[swap][:, [1, 0, 2, 3]]
    return V[order], T


def _single(rng: np.random.Generator):
    """Two random tetrahedra sharing a face, one of each orientation, far from the origin."""
    V = rng.normal(size=(5, 3)) + rng.normal(0, 10, 3)
    T = np.array([[0, 1, 2, 3], [0, 1, 2, 4]])
    signs = np.sign([np.linalg.det(V[t[1:]] - V[t[0]]) for t in T])
    T[signs != [1, -1]] = T[signs != [1, -1]][:, [1, 0, 2, 3]]  # the first positive, the second negative
    return V, T


def _meshes(rng: np.random.Generator):
    return {
        "two random tetrahedra, one of each orientation": _single(rng),
        "the hand (jittered, shuffled)": _shuffled("hand_tet", rng),
        "the volumetric bar, half the tetrahedra negatively oriented": _shuffled("bar_tet", rng, flip=True),
        "the volumetric bar stretched 3x along y (anisotropic)": (
            lambda V, T: (V * [1.0, 3.0, 1.0], T))(*_shuffled("bar_tet", rng, jitter=0.05)),
    }


def _deformed(V: np.ndarray, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Deformed copies: a rigid motion, an affine map, a bend with noise (some tetrahedra inverted)."""
    R = random_rotation(rng, 3)
    A = R @ np.diag(rng.uniform(0.5, 1.5, 3))
    centre = V.mean(axis=0)
    size = float(np.ptp(V, axis=0).max())
    angle = 0.6 * (V[:, 0] - centre[0]) / size
    bent = V.copy()
    bent[:, 1] = centre[1] + np.cos(angle) * (V[:, 1] - centre[1]) - np.sin(angle) * (V[:, 2] - centre[2])
    bent[:, 2] = centre[2] + np.sin(angle) * (V[:, 1] - centre[1]) + np.cos(angle) * (V[:, 2] - centre[2])
    return {
        "a rigid motion": V @ R.T + rng.normal(0, 2, 3),
        "an affine map": V @ A.T + rng.normal(0, 2, 3),
        "a twist with noise (some tetrahedra inverted)": bent + 0.03 * size * rng.normal(size=V.shape),
    }


class TetVolumesChecks(FunctionChecks):
    function = "tet_volumes"
    description = "signed volumes det[v1 - v0, v2 - v0, v3 - v0] / 6 on both orientations, shuffled course meshes"

    def cases(self, rng):
        return [Case.call(label, "tet_volumes", V, T) for label, (V, T) in _meshes(rng).items()]

    def verify(self, case, got, expected):
        V, T = case.args()
        vol = as_array(got, (len(T),), "vol")
        want = as_array(expected, (len(T),), "the reference's vol")
        scale = float(np.abs(want).max())
        ok, where = close(vol, want, TET_RTOL, scale)
        hint = ""
        if not ok and close(np.abs(vol), np.abs(want), TET_RTOL, scale)[0]:
            hint = " (the sizes are right but the signs are not: the volume is signed, det / 6 without abs)"
        elif not ok and (close(vol, 6 * want, TET_RTOL, scale)[0] or close(vol, -6 * want, TET_RTOL, scale)[0]):
            hint = " (six times too large: a tetrahedron is 1/6 of the parallelepiped its edges span)"
        return [verdict("vol matches, with its sign", ok, where + hint)]


class TetCotangentLaplacianChecks(FunctionChecks):
    function = "tet_cotangent_laplacian"
    description = "L[i, j] = -Σ |vol| ∇φ_i · ∇φ_j, zero row sums, equal to igl.cotmatrix, on both orientations"

    def cases(self, rng):
        return [Case.call(label, "tet_cotangent_laplacian", V, T) for label, (V, T) in _meshes(rng).items()]

    def verify(self, case, got, expected):
        V, T = case.args()
        n = len(V)
        L = as_matrix(got, (n, n), "L")
        want = as_matrix(expected, (n, n), "the reference's L")
        scale = max_abs(want)
        ok, where = close(L, want, TET_RTOL, scale)
        hint = ""
        if not ok:
            if close(L, -want, TET_RTOL, scale)[0]:
                hint = " (the signs are flipped: off-diagonal entries are -|vol| ∇φ_i · ∇φ_j, the diagonal makes rows sum to zero)"
            elif close(L, 6 * want, TET_RTOL, scale)[0]:
                hint = " (six times too large: multiply by the volume det / 6, not by det)"
            elif not close(np.asarray(L.sum(axis=1)).ravel(), 0.0, TET_RTOL, scale)[0]:
                hint = " (the rows do not sum to zero: L[i, i] is minus the sum of the row's other entries)"
        return [verdict("L matches", ok, where + hint)]


class TetMassMatrixChecks(FunctionChecks):
    function = "tet_mass_matrix"
    description = "diagonal M[i, i] = Σ |vol| / 4 over the tetrahedra around i, on both orientations"

    def cases(self, rng):
        return [Case.call(label, "tet_mass_matrix", V, T) for label, (V, T) in _meshes(rng).items()]

    def verify(self, case, got, expected):
        V, T = case.args()
        n = len(V)
        M = as_matrix(got, (n, n), "M")
        want = as_matrix(expected, (n, n), "the reference's M")
        scale = max_abs(want)
        ok, where = close(M, want, TET_RTOL, scale)
        hint = ""
        if not ok and np.any(M.diagonal() < 0):
            hint = " (negative masses: use |vol|, a negatively oriented tetrahedron still has a positive volume)"
        elif not ok and close(M, 4 * want, TET_RTOL, scale)[0]:
            hint = " (each vertex gets a quarter of each tetrahedron's volume, not all of it)"
        return [
            verdict("M is diagonal", close(M - sp.diags(M.diagonal()), 0.0, TET_RTOL, scale)[0], "off-diagonal entries"),
            verdict("M matches", ok, where + hint),
        ]


class TetBiharmonicMatrixChecks(FunctionChecks):
    function = "tet_biharmonic_matrix"
    description = "sparse Q = L M⁻¹ L with the tetrahedral L and barycentric M, on both orientations"

    def cases(self, rng):
        return [Case.call(label, "tet_biharmonic_matrix", V, T) for label, (V, T) in _meshes(rng).items()]

    def verify(self, case, got, expected):
        from .verdicts import sparse_verdict
        from . import reference as reference_function

        V, T = case.args()
        n = len(V)
        Q = as_matrix(got, (n, n), "Q")
        want = as_matrix(expected, (n, n), "the reference's Q")
        ok, where = close(Q, want, TET_RTOL, max_abs(want))
        hint = ""
        if not ok:
            L = sp.csr_matrix(reference_function("tet_cotangent_laplacian")(V, T))
            mass = reference_function("tet_mass_matrix")(V, T).diagonal()
            for wrong, why in (
                (L @ L, "M⁻¹ is missing: Q = L M⁻¹ L, not L L"),
                (L @ sp.diags(mass) @ L, "multiply by M⁻¹, not by M"),
            ):
                if close(Q, wrong, TET_RTOL, max_abs(wrong))[0]:
                    hint = f" ({why})"
                    break
        return [sparse_verdict(got), verdict("Q matches L M⁻¹ L", ok, where + hint)]


class DeformationGradientsChecks(FunctionChecks):
    function = "deformation_gradients"
    description = "J_t maps the rest edges to the deformed edges: rigid, affine and bent deformations"

    def cases(self, rng):
        cases = []
        for label, (V, T) in list(_meshes(rng).items())[:3]:
            for how, U in _deformed(V, rng).items():
                cases.append(Case.call(f"{label}, {how}", "deformation_gradients", V, U, T))
        return cases

    def verify(self, case, got, expected):
        V, U, T = case.args()
        J = as_array(got, (len(T), 3, 3), "J")
        want = as_array(expected, (len(T), 3, 3), "the reference's J")
        scale = float(np.abs(want).max())
        ok, where = close(J, want, TET_RTOL, scale)
        hint = ""
        if not ok and close(J, want.transpose(0, 2, 1), TET_RTOL, scale)[0]:
            hint = " (each J_t is transposed: J_t (v_k - v_0) = u_k - u_0, deformed edges = J times rest edges)"
        elif not ok:
            inverse = np.linalg.inv(np.where(np.abs(np.linalg.det(want))[:, None, None] > 1e-12, want, np.eye(3)))
            if close(J, inverse, TET_RTOL, float(np.abs(inverse).max()))[0]:
                hint = " (this is J⁻¹: multiply the deformed edges by the inverse of the rest edges, D' D⁻¹)"
        return [verdict("J matches (tetrahedron, row, column)", ok, where + hint)]


class TetArapRotationsChecks(FunctionChecks):
    function = "tet_arap_rotations"
    description = "R_t the rotation nearest to J_t (det +1), also on inverted and flattened tetrahedra"

    def cases(self, rng):
        cases = []
        for label, (V, T) in list(_meshes(rng).items())[:3]:
            for how, U in _deformed(V, rng).items():
                cases.append(Case.call(f"{label}, {how}", "tet_arap_rotations", V, U, T))
        V, T = _single(rng)
        U = V.copy()
        U[:, 2] = 0.0  # every tetrahedron flattened onto a plane: J has rank 2
        cases.append(Case.call("two tetrahedra flattened onto the plane z = 0", "tet_arap_rotations", V, U, T))
        return cases

    def verify(self, case, got, expected):
        V, U, T = case.args()
        R = as_array(got, (len(T), 3, 3), "R")
        want = as_array(expected, (len(T), 3, 3), "the reference's R")
        from . import reference as reference_function

        J = once_per_case(case, "J", lambda: reference_function("deformation_gradients")(V, U, T))
        gram = np.linalg.norm(np.einsum("tji,tjk->tik", R, R) - np.eye(3), axis=(1, 2))
        det = np.linalg.det(R)
        rotation = bool(gram.max() <= ROTATION_TOL and np.all(np.abs(det - 1.0) <= ROTATION_TOL))
        where = f"tetrahedron {int(np.argmax(gram + np.abs(det - 1)))}"
        if not rotation and np.any(det < 0):
            where += " has det R = -1: a reflection (flip the singular vector of the smallest singular value)"
        got_distance = np.sum((J - R) ** 2, axis=(1, 2))
        best = once_per_case(case, "nearest distances", lambda: np.sum((J - want) ** 2, axis=(1, 2)))
        slack = ROTATION_TOL * (1.0 + np.sum(J**2, axis=(1, 2)))
        nearest = bool(np.all(got_distance <= best + slack))
        worst = int(np.argmax(got_distance - best))
        hint = ""
        if not nearest and close(R, want.transpose(0, 2, 1), 1e-8)[0]:
            hint = " (R_t is transposed: maximize tr(R J_tᵀ), i.e. R = X Yᵀ for J = X Σ Yᵀ)"
        return [
            verdict("each R_t is a rotation (RᵀR = I, det R = +1)", rotation, where),
            verdict(
                "each R_t is nearest to J_t among rotations",
                nearest,
                f"tetrahedron {worst}: ‖J - R‖² = {got_distance[worst]:.6g}, the nearest rotation gives {best[worst]:.6g}{hint}",
            ),
        ]


class TetArapEnergyChecks(FunctionChecks):
    function = "tet_arap_energy"
    description = "Σ |vol| ‖J - R‖² for rotations and for arbitrary matrices, on both orientations"

    def cases(self, rng):
        cases = []
        for label, (V, T) in list(_meshes(rng).items())[:3]:
            deformed = _deformed(V, rng)
            U = deformed["a twist with noise (some tetrahedra inverted)"]
            R = np.stack([random_rotation(rng, 3) for _ in range(len(T))])
            cases.append(Case.call(f"{label}, bent, random rotations", "tet_arap_energy", V, U, T, R))
            cases.append(
                Case.call(f"{label}, affine, arbitrary matrices", "tet_arap_energy", V, deformed["an affine map"], T,
                          rng.normal(size=(len(T), 3, 3)))
            )
        return cases

    def verify(self, case, got, expected):
        V, U, T, R = case.args()
        E = as_float(got, "E")
        want = as_float(expected, "the reference's E")
        ok, where = close(E, want, TET_RTOL, abs(want))
        hint = ""
        if not ok:
            from . import reference as reference_function

            J = reference_function("deformation_gradients")(V, U, T)
            distance = np.sum((J - R) ** 2, axis=(1, 2))
            vol = reference_function("tet_volumes")(V, T)
            if np.isclose(E, float(vol @ distance), rtol=1e-9):
                hint = " (use |vol|: a negatively oriented tetrahedron must not subtract energy)"
            elif np.isclose(E, float(distance.sum()), rtol=1e-9):
                hint = " (each tetrahedron's term is weighted by its volume)"
        return [verdict("E matches", ok, f"got {E:.10g}, expected {want:.10g}{hint}" if not ok else where)]


def _arap_scenes(rng: np.random.Generator):
    """Tet meshes with handles (in random order), their targets and the rotations of a realistic local step.

    Returns ``{label: (V, T, handles, P, R)}``: the bar's two ends, the second
    twisted (also on the bar stretched 3x); the hand's wrist and fingertips
    moved (a bend with noise); two tetrahedra of opposite orientations held at
    one vertex each.
    """
    from . import reference as reference_function

    scenes = {}
    for label, (V, T), axis in (
        ("the volumetric bar, half the tetrahedra negatively oriented, ends held and twisted",
         _shuffled("bar_tet", rng, flip=True), 0),
        ("the hand (jittered, shuffled), wrist and fingertips moved", _shuffled("hand_tet", rng), 1),
        ("the volumetric bar stretched 3x along y (anisotropic), ends held and twisted",
         (lambda V, T: (V * [1.0, 3.0, 1.0], T))(*_shuffled("bar_tet", rng, jitter=0.05)), 0),
    ):
        low, high = V[:, axis].min(), V[:, axis].max()
        step = 0.05 * (high - low)
        handles = rng.permutation(np.flatnonzero((V[:, axis] <= low + step) | (V[:, axis] >= high - step)))
        U = _deformed(V, rng)["a twist with noise (some tetrahedra inverted)"]
        scenes[label] = (V, T, handles, U[handles])
    V, T = _single(rng)
    handles = np.array([4, 3])
    scenes["two random tetrahedra, one of each orientation, one vertex of each held"] = (
        V, T, handles, V[handles] + rng.normal(0, 0.3, (2, 3)))
    out = {}
    for label, (V, T, handles, P) in scenes.items():
        U = V.copy()
        U[handles] = P
        R = np.asarray(reference_function("tet_arap_rotations")(V, U, T))
        # some tetrahedra get random rotations instead, so the target is not near any ARAP iterate
        for t in np.flatnonzero(rng.uniform(size=len(T)) < 0.3):
            R[t] = random_rotation(rng, 3)
        out[label] = (V, T, handles, P, R)
    return out


def _global_step_verdicts(case, got, expected, V, T, handles, P, R) -> list:
    """Handles exact, energy at the reference's minimum for ``R``, and the same minimizer; hints for common slips."""
    import types

    from .arap import DIRECT_RTOL, SOLVE_RTOL, energy_verdict, handle_verdict, positions_verdict
    from . import reference as reference_function

    U = as_array(got, (len(V), 3), "U")
    want = as_array(expected, (len(V), 3), "the reference's U")
    energy = reference_function("tet_arap_energy")
    signed_volumes = once_per_case(case, "signed volumes", lambda: reference_function("tet_volumes")(V, T))

    def reference_terms():
        J = reference_function("deformation_gradients")(V, want, T)
        scale = float(np.abs(signed_volumes) @ (np.sum(J**2, axis=(1, 2)) + 3.0))  # bounds the energy's terms, for roundoff
        return scale, float(energy(V, want, T, R))

    scale, minimum = once_per_case(case, "energy scale and minimum", reference_terms)
    same = positions_verdict("U is the unique minimizer", U, want, V, SOLVE_RTOL)
    if not same.passed:
        precompute, step = reference_function("tet_arap_precompute"), reference_function("tet_arap_global_step")
        data = precompute(V, T, handles)
        signed = types.SimpleNamespace(**{**vars(data), "volumes": signed_volumes})
        no_columns = types.SimpleNamespace(**{**vars(data), "L_free_handles": 0.0 * data.L_free_handles})
        for variant, why in (
            (lambda: step(data, np.transpose(R, (0, 2, 1)), P), "B takes R_t ∇φ_i with R_t itself, not its transpose"),
            (lambda: step(signed, R, P), "weight B by |vol_t|: a negatively oriented tetrahedron pulls the wrong way with the signed volume"),
            (lambda: step(no_columns, R, P), "the handles' columns belong on the right-hand side: (-L)_ff U_f = B_f + L_fh U_h"),
        ):
            if positions_verdict("", U, variant(), V, SOLVE_RTOL).passed:
                same.detail += f" ({why})"
                break
    return [
        handle_verdict(U, handles, P),
        energy_verdict("minimal energy for the given rotations", float(energy(V, U, T, R)), minimum, scale, DIRECT_RTOL, at_most=True),
        same,
    ]


class TetArapPrecomputeChecks(FunctionChecks):
    function = "tet_arap_precompute"
    needs = ("tet_arap_global_step",)
    description = "the precomputed data serves several global steps in a row, handles in any order; bad handles raise ValueError"

    def cases(self, rng):
        cases, scenes = [], _arap_scenes(rng)
        for label, (V, T, handles, P, R) in scenes.items():
            P2 = P + rng.normal(0.0, 0.1, P.shape)
            R2 = np.stack([random_rotation(rng, 3) for _ in range(len(T))])
            steps = [Step("tet_arap_precompute", (V, T, handles)), Step("tet_arap_global_step", (Ref(0), R, P)),
                     Step("tet_arap_global_step", (Ref(0), R2, P2))]
            cases.append(Case(f"{label}: two global steps with one precomputation", steps, {"R": R2, "P": P2}))
        # The contract's promise: a ValueError if handles is empty, repeats a vertex or is out of range.
        V, T, handles, _, _ = next(iter(scenes.values()))
        for label, bad in bad_handle_sets(handles, len(V)):
            cases.append(raises(f"the volumetric bar with {label}", [Step("tet_arap_precompute", (V, T, bad))]))
        return cases

    def verify(self, case, got, expected):
        V, T, handles = case.args(0)
        return _global_step_verdicts(case, got, expected, V, T, handles, case.context["P"], case.context["R"])


class TetArapGlobalStepChecks(FunctionChecks):
    function = "tet_arap_global_step"
    needs = ("tet_arap_precompute",)
    description = "U minimizing the tetrahedral ARAP energy for given rotations, handles met exactly, both orientations"

    def cases(self, rng):
        return [
            Case(label, [Step("tet_arap_precompute", (V, T, handles)), Step("tet_arap_global_step", (Ref(0), R, P))])
            for label, (V, T, handles, P, R) in _arap_scenes(rng).items()
        ]

    def verify(self, case, got, expected):
        V, T, handles = case.args(0)
        _, R, P = case.args(1)
        return _global_step_verdicts(case, got, expected, V, T, handles, P, R)
