"""What a check is: hidden cases for one contract function and the verdicts on its outputs.

Verdicts are computed here, in the grading process, with trusted numpy, from
the student's raw outputs (already plain arrays, ``grader.harness.outputs``)
and the reference's outputs on the same inputs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
import scipy.sparse as sp

from grader.harness.fixtures import Case, Ref, Step

__all__ = [
    "Case",
    "Ref",
    "Step",
    "Verdict",
    "FunctionChecks",
    "ShapeError",
    "as_array",
    "as_matrix",
    "as_int",
    "as_float",
    "as_pair",
    "close",
    "once_per_case",
    "raises",
    "raised_verdict",
    "verdict",
]


@dataclass
class Verdict:
    """One named property of one case, e.g. ``det = +1``."""

    name: str
    passed: bool
    detail: str = ""


def verdict(name: str, passed: bool, detail: str = "") -> Verdict:
    return Verdict(name, bool(passed), "" if passed else detail)


def raises(label: str, steps: list[Step], error: str = "ValueError") -> Case:
    """A case whose last step must raise ``error`` (a contract promise for bad input), not return.

    The reference is not run on it (``reference_outputs`` gives ``None``); tests check that it raises.
    """
    return Case(label, steps, {"raises": error})


def raised_verdict(error: str, raised: str | None) -> Verdict:
    """Whether the call raised ``error``, from what the collection recorded.

    ``raised`` is the recorded ``"TypeName: message"`` (``None`` if the call returned). Only the
    class name travels from the kernel, so a subclass of ``ValueError`` (``LinAlgError`` from a
    singular solve, say) is not the clear error the contract asks for.
    """
    name = None if raised is None else raised.split(":", 1)[0].strip()
    if name is None or not name.isidentifier():  # the call returned (its output may not even have been readable)
        return verdict(f"raises {error}", False, f"returned a result instead of raising {error}")
    return verdict(f"raises {error}", name == error, f"raised {raised.splitlines()[0][:300]}, not {error}")


class ShapeError(ValueError):
    """The output's type or shape is not what the contract says."""


def as_array(value: Any, shape: tuple | None = None, what: str = "output", dtype=np.float64) -> np.ndarray:
    """Plain finite ``dtype`` array of the given shape (``None`` entries match any size).

    Raises
    ------
    ShapeError
        Naming the expected and found shape, or the first non-finite entry.
    """
    if sp.issparse(value):
        value = value.toarray()
    if isinstance(value, tuple):
        raise ShapeError(f"{what} should be an array, got a tuple of {len(value)} items")
    try:
        a = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{what} is not numeric: {exc}") from None
    if shape is not None and (a.ndim != len(shape) or any(s is not None and s != t for s, t in zip(shape, a.shape))):
        raise ShapeError(f"{what} should have shape {_shape_text(shape)}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
        raise ShapeError(f"{what} has NaN or inf (first at index {bad})")
    if dtype is not np.float64:
        if not np.all(a == np.round(a)):
            raise ShapeError(f"{what} should hold integers")
        a = a.astype(dtype)
    return a


def _shape_text(shape: tuple) -> str:
    return "(" + ", ".join("?" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def as_matrix(value: Any, shape: tuple[int, int], what: str = "output") -> sp.csr_matrix:
    """Finite float64 CSR matrix of the given shape, from a sparse or a dense output.

    A sparse output is never densified: an n x n Laplacian of a tet mesh is 11 MB dense.

    Raises
    ------
    ShapeError
        Naming the expected and found shape, or the first non-finite entry.
    """
    if not sp.issparse(value):
        return sp.csr_matrix(as_array(value, shape, what))
    if value.shape != tuple(shape):
        raise ShapeError(f"{what} should have shape {_shape_text(shape)}, got {value.shape}")
    try:
        a = sp.csr_matrix(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ShapeError(f"{what} is not numeric: {exc}") from None
    a.sum_duplicates()  # canonical: entries in row-major order, as as_array reports them
    bad = np.flatnonzero(~np.isfinite(a.data))
    if bad.size:
        row = int(np.searchsorted(a.indptr, bad[0], side="right")) - 1
        raise ShapeError(f"{what} has NaN or inf (first at index {(row, int(a.indices[bad[0]]))})")
    return a


def max_abs(a) -> float:
    """Largest absolute entry of a dense or sparse array (0 when it has none)."""
    if sp.issparse(a):
        return float(abs(a).max()) if a.nnz else 0.0
    a = np.asarray(a, float)
    return float(np.abs(a).max()) if a.size else 0.0


def as_int(value: Any, what: str = "output") -> int:
    a = as_array(value, (), what)
    if a != np.round(a):
        raise ShapeError(f"{what} should be an integer, got {float(a)}")
    return int(a)


def as_float(value: Any, what: str = "output") -> float:
    return float(as_array(value, (), what))


def as_pair(value: Any, what: str = "output") -> tuple:
    if not isinstance(value, tuple) or len(value) != 2:
        raise ShapeError(f"{what} should be a pair (a tuple of 2), got {type(value).__name__}")
    return value


def close(a: np.ndarray, b: np.ndarray, tol: float, scale: float = 1.0) -> tuple[bool, str]:
    """``max |a - b| <= tol * max(scale, 1)``; also reports where the worst entry is.

    ``a`` and ``b`` may be sparse (then only their stored entries are visited), ``b`` a scalar.
    """
    if sp.issparse(a) or sp.issparse(b):
        return _close_sparse(a, b, tol, scale)
    err = np.abs(np.asarray(a, float) - np.asarray(b, float))
    if err.size == 0:
        return True, ""
    worst = np.unravel_index(int(np.argmax(err)), err.shape)
    ok = float(err[worst]) <= tol * max(scale, 1.0)
    return ok, f"largest difference {float(err[worst]):.3g} at index {tuple(int(i) for i in worst)}"


def once_per_case(case: Case, key: str, compute: Callable[[], Any]) -> Any:
    """``compute()``, computed once per case and process and kept in ``case.context[key]``.

    For what depends on the hidden case and the reference's output alone: the cases
    are cached per process (``grader.checks.seeded_cases``), so every later student's
    verification reuses it.
    """
    if key not in case.context:
        case.context[key] = compute()
    return case.context[key]


def _close_sparse(a, b, tol: float, scale: float) -> tuple[bool, str]:
    a = sp.csr_matrix(a, dtype=np.float64)
    if a.shape[0] * a.shape[1] == 0:
        return True, ""
    err = abs(a) if np.ndim(b) == 0 and float(b) == 0.0 else abs(a - sp.csr_matrix(b, dtype=np.float64))
    err.sum_duplicates()
    err.eliminate_zeros()  # entries that cancelled: a dense comparison names (0, 0) when nothing differs
    err = err.tocoo()  # row-major, as a dense argmax scans
    if err.nnz == 0:
        worst, largest = (0, 0), 0.0
    else:
        k = int(np.argmax(err.data))
        worst, largest = (int(err.row[k]), int(err.col[k])), float(err.data[k])
    ok = largest <= tol * max(scale, 1.0)
    return ok, f"largest difference {largest:.3g} at index {worst}"


class FunctionChecks:
    """Hidden cases and verdicts for one contract function.

    Subclasses set ``function`` and implement ``cases`` and ``verify``.

    Attributes
    ----------
    function : str
        The contract function checked.
    needs : tuple of str
        Other graded functions the cases call (a precomputation's cases call the step that uses it).
    assignment : str
        The assignment whose pack declares these checks (set when the engine registers them).
    description : str
        One line shown in feedback and in the notebook's hidden section.
    """

    function: str = ""
    needs: tuple[str, ...] = ()
    assignment: str = ""
    description: str = ""

    def cases(self, rng: np.random.Generator) -> list[Case]:
        raise NotImplementedError

    def verify(self, case: Case, got: Any, expected: Any) -> list[Verdict]:
        """Verdicts for one case; may raise ``ShapeError`` (one failed verdict)."""
        raise NotImplementedError


def run_steps(case: Case, resolve: Callable[[str], Callable]) -> Any:
    """Run a case's steps with functions from ``resolve`` (the reference, or a namespace)."""
    results: list[Any] = []

    def decode(v):
        if isinstance(v, Ref):
            return results[v.step]
        if isinstance(v, np.ndarray):
            return v.copy()
        if isinstance(v, list):
            return [decode(x) for x in v]
        if isinstance(v, tuple):
            return tuple(decode(x) for x in v)
        return v

    for step in case.steps:
        fn = resolve(step.function)
        results.append(fn(*[decode(a) for a in step.args], **{k: decode(v) for k, v in step.kwargs.items()}))
    return results[-1]
