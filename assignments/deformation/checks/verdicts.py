"""Verdicts more than one stage's checks give."""

from __future__ import annotations

import scipy.sparse as sp

from grader.checks.base import Verdict, verdict


def sparse_verdict(got) -> Verdict:
    """The contract's sparse matrices must come back sparse (the wire rebuilds them as CSR)."""
    return verdict("a scipy.sparse matrix", sp.issparse(got), f"returned a dense {type(got).__name__}; the contract asks for a scipy.sparse matrix")
