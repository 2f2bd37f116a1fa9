"""Checks of stage 02 (sign correction): the best rotation, alone and for aligning point sets.

A rotation is judged by orthonormality, ``det R = +1`` and ``tr(R S)`` against
the reference's ``tr(R_ref S)``; ``R`` itself is never compared, since any
maximizer is correct when ``S`` is rank-deficient.
"""

from __future__ import annotations

import numpy as np

from grader.checks.base import Case, FunctionChecks, Verdict, as_array, verdict
from .generators import random_rotation
from .shape_matching import align_cases, align_verdicts, matrix_cases, orthonormal_verdict, trace_verdict

#: Largest ``|det R − 1|`` accepted for a rotation.
DET_TOL = 1e-8


def det_verdict(R: np.ndarray, what: str = "R") -> Verdict:
    """``det R = +1`` within ``DET_TOL`` for a ``(d, d)`` matrix or each of a ``(k, d, d)`` stack."""
    det = np.reshape(np.linalg.det(R), -1)
    worst = int(np.argmax(np.abs(det - 1.0)))
    where = f" of matrix {worst}" if R.ndim == 3 else ""
    hint = " (a reflection: the sign was not corrected)" if det[worst] < 0 else ""
    return verdict("det = +1", abs(det[worst] - 1.0) <= DET_TOL, f"det{where} of {what} is {det[worst]:.10g}{hint}")


def rotation_verdicts(R: np.ndarray, what: str = "R") -> list[Verdict]:
    """Orthonormal and ``det = +1``, for one matrix or a stack."""
    return [orthonormal_verdict(R, what), det_verdict(R, what)]


def exactly_singular(rng: np.random.Generator, k: int = 6) -> np.ndarray:
    """``(k, 3, 3)``: ``S = diag(a, 0, c) Bᵀ`` for random rotations ``B``, so ``det S`` is exactly 0.

    The best rotation is ``B``. LAPACK's singular vectors of the zero singular value give
    ``det(Ṽ Ũᵀ) = -1`` for about half of these (measured), so a sign taken from ``det S``
    instead of ``det(Ṽ Ũᵀ)`` misses ``B`` in all but one of 2^k draws.
    """
    return np.stack([np.diag([rng.uniform(2.0, 3.0), 0.0, rng.uniform(0.5, 1.5)]) @ random_rotation(rng, 3).T for _ in range(k)])


class OptimalRotationChecks(FunctionChecks):
    function = "optimal_rotation"
    description = "rotations maximizing tr(R S) for single S and (k, d, d) stacks: mirrored, rank-deficient, zero S"

    def cases(self, rng):
        three, two = matrix_cases(rng, 3), matrix_cases(rng, 2)
        singles = [
            (label, S)
            for label, S in [*three.items(), *two.items()]
            if label in ("generic 3x3", "3x3 with det < 0 (mirrored points)", "2x2 with det < 0 (mirrored points)", "rank 2 (planar 3D points)")
        ]
        stacks = [
            (f"stack of {len(three)} 3x3: " + ", ".join(three), np.stack(list(three.values()))),
            (f"stack of {len(two)} 2x2: " + ", ".join(two), np.stack(list(two.values()))),
            ("stack of one 3x3 with det < 0", three["det < 0 with smallest singular value 1e-9"][None]),
            ("stack of 6 planar 3x3 with a zero row (det S exactly 0; the sign comes from det(Ṽ Ũᵀ))", exactly_singular(rng)),
        ]
        return [Case.call(label, "optimal_rotation", S) for label, S in singles + stacks]

    def verify(self, case, got, expected):
        S = case.args()[0]
        R = as_array(got, S.shape, "R")
        R_ref = as_array(expected, S.shape, "the reference's R")
        best = np.einsum("...ij,...ji->...", R_ref, S)
        return rotation_verdicts(R) + [trace_verdict(R, S, best, "optimal tr(R S) over rotations")]


class RigidAlignChecks(FunctionChecks):
    function = "rigid_align"
    description = "(R, t) with R a rotation minimizing Σ w‖R p + t − q‖², also for mirrored, planar and collinear points"

    def cases(self, rng):
        return align_cases("rigid_align", rng)

    def verify(self, case, got, expected):
        return align_verdicts(case, got, expected, rotation_verdicts)
