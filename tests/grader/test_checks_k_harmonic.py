"""The stage 02b checks fail realistic mistakes, name them, and hold solves to answers known in closed form."""

from __future__ import annotations

import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import reference.k_harmonic as ref
from grader.checks import check_namespace


def grade(function, implementation, **others):
    """The checks' result for the reference with ``function`` (and ``others``) replaced."""
    return check_namespace(function, {**vars(ref), function: implementation, **others})


def details(result) -> str:
    return " ".join(v.detail for c in result.cases for v in c.verdicts if not v.passed)


def precompute(sort=False):
    def k_harmonic_precompute(Q, handles):
        Q = sp.csr_matrix(Q)
        handles = np.unique(handles) if sort else np.array(handles, dtype=np.int64)
        free = np.setdiff1d(np.arange(Q.shape[0]), handles)
        return types.SimpleNamespace(n=Q.shape[0], handles=handles, free=free, Q_fh=Q[free][:, handles],
                                     Q_ff=spla.splu(Q[free][:, free].tocsc()))

    return k_harmonic_precompute


def solve(rhs=lambda data, D_h: -(data.Q_fh @ D_h)):
    def k_harmonic_solve(data, handle_displacements):
        D_h = np.asarray(handle_displacements, dtype=float)
        D = np.zeros((data.n, D_h.shape[1]))
        D[data.handles] = D_h
        D[data.free] = data.Q_ff.solve(rhs(data, D_h))
        return D

    return k_harmonic_solve


def test_the_reference_and_a_plain_elimination_pass_every_case_including_the_closed_form_ones():
    result = check_namespace("k_harmonic_solve", vars(ref))
    assert result.fraction == 1.0
    names = {v.name for c in result.cases for v in c.verdicts}
    assert {"every vertex moves by the handles' translation", "the affine displacement is reproduced exactly"} <= names
    assert grade("k_harmonic_solve", solve(), k_harmonic_precompute=precompute()).fraction == 1.0


def test_a_solve_without_the_handles_on_the_right_hand_side_fails_even_the_translation_and_says_why():
    result = grade("k_harmonic_solve", solve(rhs=lambda data, D_h: np.zeros((len(data.free), D_h.shape[1]))), k_harmonic_precompute=precompute())
    assert result.fraction == 0.0
    assert {"every vertex moves by the handles' translation", "the affine displacement is reproduced exactly"} <= result.failed_verdicts()
    assert "belong on the right-hand side" in details(result)


def test_a_solve_with_the_wrong_sign_fails_with_its_hint():
    result = grade("k_harmonic_solve", solve(rhs=lambda data, D_h: data.Q_fh @ D_h), k_harmonic_precompute=precompute())
    assert result.fraction == 0.0 and "wrong sign" in details(result)


def test_a_precomputation_that_sorts_the_handles_fails_the_problems_with_handles_out_of_order():
    result = grade("k_harmonic_solve", solve(), k_harmonic_precompute=precompute(sort=True))
    failed = [c.label for c in result.cases if not c.passed]
    assert any("translation" not in label for label in failed) and "handles' displacements met exactly" in result.failed_verdicts()
    # a common translation is the same for every handle: sorting them cannot show there
    assert all(c.passed for c in result.cases if "translation" in c.label)
