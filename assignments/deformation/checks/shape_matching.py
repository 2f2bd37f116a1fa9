"""Checks of stage 01 (centroid, covariance, best orthogonal map), and the point sets they share with stage 02.

Where the best map is not unique (rank-deficient ``S``) any maximizer is
correct, so orthogonal maps are judged by orthonormality and by the value of
``tr(R S)`` or of the alignment objective, never by comparing ``R`` itself.
"""

from __future__ import annotations

import numpy as np

from grader.checks.base import Case, FunctionChecks, Verdict, as_array, as_pair, close, verdict
from .generators import random_rotation, similar_copy

#: Largest ‖RᵀR − I‖ (Frobenius) accepted for an orthogonal matrix.
ORTHONORMAL_TOL = 1e-8
#: Relative slack on ``tr(R S)`` and on the alignment objective.
OPTIMALITY_RTOL = 1e-8


def alignment_point_sets(rng: np.random.Generator) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray | None]]:
    """Hidden ``(label, P, Q, w)`` point-set pairs, ``w`` None for unweighted.

    Includes noisy rigid copies in 2D and 3D, mirrored copies (the best
    orthogonal map is a reflection), planar and collinear sets (rank-deficient
    covariance), a coincident target, rotations near 180°, zero weights and
    a far-off origin, and a whole problem scaled down and moved far away.
    """
    sets = []

    def rigid(P, R, noise=0.01):
        return P @ R.T + rng.normal(0.0, 3.0, P.shape[1]) + rng.normal(0.0, noise, P.shape)

    P = rng.normal(size=(25, 3))
    sets.append(("3D noisy rotated copy", P, rigid(P, random_rotation(rng, 3)), None))
    P = rng.normal(size=(15, 2))
    Q, w = rigid(P, random_rotation(rng, 2), 0.05), rng.uniform(0.1, 3.0, 15)
    sets.append(("2D weighted, noisy rotated copy", P, Q, w))
    move = similar_copy(rng, 2, 0.01, 50.0)
    sets.append(("the 2D weighted problem again, scaled by 1/100, turned and moved 50 units away", move(P), move(Q), w))
    P = np.c_[rng.normal(size=(12, 2)), np.zeros(12)]
    sets.append(("planar 3D points (z = 0), rotation by nearly 180°", P, rigid(P, random_rotation(rng, 3, np.pi - 1e-3), 0.0), None))
    P = np.outer(rng.normal(size=9), rng.normal(size=3)) + rng.normal(size=3)
    sets.append(("collinear 3D points", P, rigid(P, random_rotation(rng, 3), 0.0), rng.uniform(0.5, 2.0, 9)))
    P = rng.normal(size=(20, 3)) * [3.0, 1.0, 0.3]
    sets.append(("mirrored 3D copy", P, rigid(P * [1.0, -1.0, 1.0], random_rotation(rng, 3)), None))
    P = rng.normal(size=(10, 2))
    sets.append(("mirrored 2D copy, rotation by nearly 180°", P, rigid(P * [-1.0, 1.0], random_rotation(rng, 2, np.pi - 1e-2), 0.02), None))
    P = rng.normal(size=(16, 3)) + 1e3
    w = rng.uniform(0.2, 2.0, 16)
    w[rng.choice(16, 5, replace=False)] = 0.0
    Q = rigid(P, random_rotation(rng, 3), 0.05)
    Q[w == 0] += rng.normal(0.0, 50.0, (5, 3))  # outliers that only zero weights make harmless
    sets.append(("3D, far from the origin, some zero weights on outliers", P, Q, w))
    P = rng.normal(size=(6, 3))
    sets.append(("coincident target points", P, np.tile(rng.normal(size=3), (6, 1)), None))
    return sets


def alignment_objective(R: np.ndarray, t: np.ndarray, P: np.ndarray, Q: np.ndarray, w: np.ndarray | None) -> float:
    """``Σ w_i ‖R p_i + t - q_i‖²`` for ``R`` ``(d, d)``, ``t`` ``(d,)``, ``P``, ``Q`` ``(k, d)``, ``w`` ``(k,)`` or None (unit weights)."""
    w = np.ones(len(P)) if w is None else w
    return float(w @ np.sum((P @ R.T + t - Q) ** 2, axis=1))


def spread(X: np.ndarray, w: np.ndarray | None) -> float:
    """``Σ w_i ‖x_i - x̄‖²`` of ``X`` ``(k, d)`` with the weighted centroid ``x̄`` (unit weights when ``w`` is None)."""
    w = np.ones(len(X)) if w is None else w
    return float(w @ np.sum((X - w @ X / w.sum()) ** 2, axis=1))


def alignment_scale(P: np.ndarray, Q: np.ndarray, w: np.ndarray | None) -> float:
    """``spread(P) + spread(Q)``: the size of the alignment objective, for tolerances."""
    return spread(P, w) + spread(Q, w)


def orthonormal_verdict(R: np.ndarray, what: str = "R") -> Verdict:
    """``‖RᵀR − I‖ ≤ ORTHONORMAL_TOL`` for a ``(d, d)`` matrix or each of a ``(k, d, d)`` stack; the detail names the worst."""
    stack = R.reshape(-1, *R.shape[-2:])
    err = np.linalg.norm(np.swapaxes(stack, 1, 2) @ stack - np.eye(R.shape[-1]), axis=(1, 2))
    worst = int(np.argmax(err))
    where = f" of matrix {worst}" if R.ndim == 3 else ""
    return verdict("orthonormal", err[worst] <= ORTHONORMAL_TOL, f"‖RᵀR − I‖{where} of {what} is {err[worst]:.3g}")


def trace_verdict(R: np.ndarray, S: np.ndarray, best: np.ndarray, name: str) -> Verdict:
    """``tr(R S) ≥ best − tol`` for ``(d, d)`` matrices or ``(k, d, d)`` stacks, ``best`` a float or ``(k,)``, ``tol`` relative to ``Σσ(S)``."""
    R3, S3 = R.reshape(-1, *R.shape[-2:]), S.reshape(-1, *S.shape[-2:])
    found = np.einsum("kij,kji->k", R3, S3)
    tol = OPTIMALITY_RTOL * np.maximum(1.0, np.linalg.svd(S3, compute_uv=False).sum(axis=1))
    short = np.reshape(best, -1) - found - tol
    worst = int(np.argmax(short))
    where = f" for matrix {worst} of the stack" if R.ndim == 3 else ""
    return verdict(
        name,
        short[worst] <= 0.0,
        f"tr(R S){where} is {found[worst]:.10g}, but {np.reshape(best, -1)[worst]:.10g} is reachable",
    )


def align_verdicts(case: Case, got, expected, check_rotation) -> list[Verdict]:
    """Verdicts for an ``(R, t)`` output of ``case`` (its context holds ``P``, ``Q``, ``w``).

    Checks the shapes ``(d, d)`` and ``(d,)`` (``ShapeError`` otherwise), then
    ``check_rotation(R)`` (a list of verdicts), then the objective against the
    reference's ``(R, t)``.
    """
    P, Q, w = case.context["P"], case.context["Q"], case.context["w"]
    d = P.shape[1]
    R_got, t_got = as_pair(got, "(R, t)")
    R = as_array(R_got, (d, d), "R")
    t = as_array(t_got, (d,), "t")
    R_ref, t_ref = (as_array(x) for x in as_pair(expected, "the reference's (R, t)"))
    found = alignment_objective(R, t, P, Q, w)
    best = alignment_objective(R_ref, t_ref, P, Q, w)
    tol = OPTIMALITY_RTOL * max(1.0, alignment_scale(P, Q, w))
    return check_rotation(R) + [
        verdict(
            "optimal Σ w‖R p + t − q‖²",
            found <= best + tol,
            f"the objective of (R, t) is {found:.10g}, the best is {best:.10g}",
        )
    ]


def _point_set_case(function: str, label: str, P, Q, w, weighted_kwarg: bool) -> Case:
    """``function(P, Q[, w])``; weights go by keyword ``w`` in some cases, positionally in others."""
    args = (P,) if Q is None else (P, Q)
    if w is None:
        case = Case.call(label, function, *args)
    elif weighted_kwarg:
        case = Case.call(label, function, *args, w=w)
    else:
        case = Case.call(label, function, *args, w)
    case.context.update(P=P, Q=Q, w=w)
    return case


def align_cases(function: str, rng: np.random.Generator) -> list[Case]:
    """Hidden cases of an alignment function ``function(P, Q, w=None)``."""
    return [
        _point_set_case(function, label, P, Q, w, weighted_kwarg=i % 2 == 0)
        for i, (label, P, Q, w) in enumerate(alignment_point_sets(rng))
    ]


class CentroidChecks(FunctionChecks):
    function = "centroid"
    description = "weighted and unweighted means in 2D and 3D, zero weights, a single point, far from the origin"

    def cases(self, rng):
        w_zero = rng.uniform(0.5, 2.0, 12)
        w_zero[rng.choice(12, 4, replace=False)] = 0.0
        P_outliers = rng.normal(size=(12, 3))
        P_outliers[w_zero == 0] += 100.0
        sets = [
            ("3D unweighted", rng.normal(size=(20, 3)), None),
            ("2D weighted", rng.normal(size=(9, 2)) * 4.0, rng.uniform(0.1, 5.0, 9)),
            ("3D, zero weights on outliers", P_outliers, w_zero),
            ("single 2D point", rng.normal(size=(1, 2)), None),
            ("3D weighted, far from the origin", rng.normal(size=(7, 3)) + 1e4, rng.uniform(0.1, 1.0, 7)),
            ("2D unnormalized weights on collinear points", np.outer(rng.normal(size=6), [1.0, -2.0]), rng.uniform(5.0, 50.0, 6)),
        ]
        return [_point_set_case("centroid", label, P, None, w, weighted_kwarg=i % 2 == 0) for i, (label, P, w) in enumerate(sets)]

    def verify(self, case, got, expected):
        P = case.context["P"]
        c = as_array(got, (P.shape[1],), "centroid")
        want = as_array(expected, (P.shape[1],), "the reference's centroid")
        ok, _ = close(c, want, 1e-12, scale=float(np.abs(P).max()))
        return [verdict("weighted mean", ok, f"returned {c.tolist()}, expected {want.tolist()}")]


class CovarianceMatrixChecks(FunctionChecks):
    function = "covariance_matrix"
    description = "S = Σ w (p − p̄)(q − q̄)ᵀ with weighted centroids, in 2D and 3D, weighted and unweighted"

    def cases(self, rng):
        return align_cases("covariance_matrix", rng)

    def verify(self, case, got, expected):
        P, Q, w = case.context["P"], case.context["Q"], case.context["w"]
        d = P.shape[1]
        S = as_array(got, (d, d), "S")
        want = as_array(expected, (d, d), "the reference's S")
        wts = np.ones(len(P)) if w is None else w
        size = np.sqrt(spread(P, w) * spread(Q, w))
        ok, where = close(S, want, 1e-10, scale=size)
        # Name the usual mistakes when they explain the output.
        hint = ""
        if not ok:
            uncentred = P.T @ (wts[:, None] * Q)
            plain = (P - P.mean(0)).T @ (wts[:, None] * (Q - Q.mean(0)))
            if close(S, uncentred, 1e-10, size)[0]:
                hint = " (the points were not centred)"
            elif close(S, plain, 1e-10, size)[0]:
                hint = " (the centroids were not weighted)"
            elif close(S, want.T, 1e-10, size)[0]:
                hint = " (S is transposed: p̄ goes on the left, (p − p̄)(q − q̄)ᵀ)"
        return [verdict("S matches", ok, f"{where}{hint}")]


def matrix_cases(rng: np.random.Generator, d: int) -> dict[str, np.ndarray]:
    """Hidden ``(d, d)`` matrices ``S`` by label: generic, mirrored (det < 0), rank-deficient and zero."""
    R = random_rotation(rng, d)
    A = rng.normal(size=(d, d))
    mirror = np.diag([-1.0] + [1.0] * (d - 1))
    u, v = rng.normal(size=d), rng.normal(size=d)
    sets = [
        (f"generic {d}x{d}", A),
        (f"{d}x{d} with det < 0 (mirrored points)", R @ mirror @ np.diag(rng.uniform(0.5, 3.0, d)) @ random_rotation(rng, d).T),
        (f"rank 1 ({d}D collinear points)", np.outer(u, v)),
        (f"{d}x{d} zero matrix (coincident points)", np.zeros((d, d))),
        (f"-I ({d}D point reflection)", -np.eye(d) * rng.uniform(0.5, 2.0)),
    ]
    if d == 3:
        planar = rng.normal(size=(3, 2)) @ rng.normal(size=(2, 3))
        sets.append(("rank 2 (planar 3D points)", planar))
        # Sign correction must flip the column of the tiny singular value, not another one.
        sets.append(("det < 0 with smallest singular value 1e-9", R @ np.diag([3.0, 1.0, 1e-9]) @ mirror @ random_rotation(rng, 3).T))
    return dict(sets)


class OptimalOrthogonalChecks(FunctionChecks):
    function = "optimal_orthogonal"
    description = "orthonormal R with tr(R S) = Σσ(S), for generic, mirrored, rank-deficient and zero S"

    def cases(self, rng):
        three, two = matrix_cases(rng, 3), matrix_cases(rng, 2)
        picks = [(label, S) for label, S in three.items() if not label.startswith("-I")] + list(two.items())[:2]
        return [Case.call(label, "optimal_orthogonal", S) for label, S in picks]

    def verify(self, case, got, expected):
        S = case.args()[0]
        R = as_array(got, S.shape, "R")
        best = np.linalg.svd(S, compute_uv=False).sum()
        return [orthonormal_verdict(R), trace_verdict(R, S, best, "optimal tr(R S) over orthogonal R")]


class OrthogonalAlignChecks(FunctionChecks):
    function = "orthogonal_align"
    description = "(R, t) with R orthogonal (reflections allowed) minimizing Σ w‖R p + t − q‖²"

    def cases(self, rng):
        return align_cases("orthogonal_align", rng)

    def verify(self, case, got, expected):
        return align_verdicts(case, got, expected, lambda R: [orthonormal_verdict(R)])

