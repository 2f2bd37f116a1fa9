"""Trusted verifiers: the hidden checks of a course pack, keyed by (assignment, function).

``all_checks(assignment)[name]`` gives the checks of graded function ``name``,
every ``FunctionChecks`` subclass of the pack's ``checks`` package; ``evaluate``
turns a student's collected outputs into verdicts and a score fraction.
"""

from __future__ import annotations

import functools
import importlib
import pkgutil
import traceback
import zlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from grader.checks import callees
from grader.checks.base import Case, FunctionChecks, ShapeError, Verdict, raised_verdict, run_steps
from grader.course_pack import pack
from grader.harness.outputs import MAX_CALLS, RECORD_ELEMENTS, CaseOutput


@functools.cache
def all_checks(assignment: str | None = None) -> dict[str, FunctionChecks]:
    """Graded function name -> its checks, from every module of the pack's ``checks`` package.

    Raises
    ------
    grader.course_pack.PackError
        If a graded function has no checks, or two classes check one function.
    """
    course = pack(assignment)
    package = course.checks_module()
    modules = [package] + [
        importlib.import_module(f"{package.__name__}.{info.name}") for info in pkgutil.iter_modules(package.__path__)
    ]
    found: dict[str, FunctionChecks] = {}
    for module in modules:
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, FunctionChecks) and obj.function and obj.__module__ == module.__name__:
                if obj.function in found:
                    raise ValueError(f"{course.name}: two classes check {obj.function!r}: {type(found[obj.function]).__name__} and {obj.__name__}")
                checks = obj()
                checks.assignment = course.name
                found[obj.function] = checks
    missing = sorted(course.function_names - set(found))
    if missing:
        raise ValueError(f"assignment {course.name!r}: no hidden checks for {missing} in {package.__name__}")
    return found


@dataclass
class CaseResult:
    label: str
    verdicts: list[Verdict]
    error: str | None = None
    seconds: float | None = None
    #: the course functions whose own (wrong) outputs explain this case's output: it passed on its own work
    own_work_of: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        return self.error is None and all(v.passed for v in self.verdicts)


@dataclass
class FunctionResult:
    function: str
    cases: list[CaseResult] = field(default_factory=list)
    error: str | None = None  # a failure of the whole collection (kernel died, timeout, ...)
    #: library routines the course's policy forbids here that the function called (it then scores 0)
    policy_violations: tuple[str, ...] = ()

    @property
    def fraction(self) -> float:
        if self.error is not None or not self.cases:
            return 0.0
        return sum(c.passed for c in self.cases) / len(self.cases)

    def failed_verdicts(self) -> set[str]:
        """Names of the failed verdicts, plus ``"error"`` if a case raised."""
        names = {v.name for c in self.cases for v in c.verdicts if not v.passed}
        return names | ({"error"} if any(c.error for c in self.cases) else set())

    def summary(self) -> str:
        if self.error:
            return self.error
        failed = [c for c in self.cases if not c.passed]
        if not failed:
            callees = sorted({n for c in self.cases for n in c.own_work_of})
            if callees:
                given = sum(bool(c.own_work_of) for c in self.cases)
                return (
                    f"all {len(self.cases)} hidden cases passed ({given} judged with your own "
                    f"{', '.join(callees)}: a mistake there is charged where it is graded, not here)"
                )
            return f"all {len(self.cases)} hidden cases passed"
        first = failed[0]
        why = first.error or next(f"{v.name}: {v.detail}" for v in first.verdicts if not v.passed)
        return f"{len(failed)} of {len(self.cases)} hidden cases failed; first: {first.label}: {why}"


def charge_policy(result: FunctionResult, violations: tuple[str, ...]) -> FunctionResult:
    """``result`` scoring 0 if the function called library routines the course's policy forbids in it.

    The verdicts of its cases stay (the feedback shows them); the error names every routine.
    """
    if not violations:
        return result
    from starter.library_policy import message

    result.policy_violations = tuple(violations)
    result.error = "; ".join(message(result.function, r) for r in violations)
    return result


def reference_outputs(cases: list[Case], assignment: str | None = None) -> list[Any]:
    """The reference's output on every case, computed in this (trusted) process (``None`` for a case that must raise)."""
    function = pack(assignment).reference_function
    return [None if "raises" in case.context else run_steps(case, function) for case in cases]


#: (assignment, function) -> the course functions its reference called on its hidden cases (``callees.trace``)
_REACHED: dict[tuple[str, str], frozenset[str]] = {}


def record_plan(function: str, seed: int | tuple[int, ...] = 0, assignment: str | None = None) -> dict:
    """What the collector records while ``function`` is collected: the course functions a rerun may need.

    Sent to the kernel with the fixtures: names, the sketches' seed and the recordings' budget; never an expected value.
    """
    assignment = pack(assignment).name
    seeded_cases(function, seed, assignment)  # fills _REACHED
    course = callees.course_callees(pack(assignment))
    return {
        "names": callees.recorded_names(course, function, _REACHED[(assignment, function)]),
        "batched": {name: param for name, (param, _) in course.batched.items()},
        "seed": sketch_seed(seed),
        "budget": RECORD_ELEMENTS,
        "max_calls": MAX_CALLS,
    }


def sketch_seed(seed: int | tuple[int, ...]) -> int:
    """The seed of the argument sketches for a run's ``seed``: a plain integer under 2**31."""
    return zlib.crc32(repr(seed).encode()) & 0x7FFFFFFF


def _own_work(checks: FunctionChecks, case: Case, out: CaseOutput, seed) -> tuple[str, ...]:
    """The callees whose student outputs explain ``out`` (empty if they do not, or nothing was substituted).

    An error explains itself when the contract's function raises the same
    ``ValueError`` on the student's callee outputs.
    """
    if not out.calls or seed is None:
        return ()
    course = callees.course_callees(pack(checks.assignment))
    rerun = callees.own_work_output(course, case, out.calls, checks.function, sketch_seed(seed))
    if rerun is None or not rerun[1]:
        return ()
    output, substituted, raised = rerun
    if raised is not None:
        explained = out.error is not None and out.error.startswith(f"{raised}:")
    else:
        explained = out.error is None and callees.matches_own_work(out.value, output)
    return tuple(sorted(substituted)) if explained else ()


def evaluate(
    checks: FunctionChecks, cases: list[Case], outputs: list[CaseOutput], expected: list[Any], seed=None
) -> FunctionResult:
    """Verdicts for every case; a check that crashes on odd output fails that case, never the run.

    With the run's ``seed``, a case the verdicts fail passes when the student's
    output is the reference's given the student's own outputs of the course
    functions it called (``grader.checks.callees``): a bug is charged once.
    """
    result = FunctionResult(checks.function)
    for case, out, ref in zip(cases, outputs, expected):
        if "raises" in case.context:  # a contract promise for bad input: the call must raise, not return
            result.cases.append(CaseResult(case.label, [raised_verdict(case.context["raises"], out.error)], seconds=out.seconds))
            continue
        if out.error is not None:
            given = _own_work(checks, case, out, seed)
            if given:
                result.cases.append(CaseResult(case.label, [Verdict("own work", True)], seconds=out.seconds, own_work_of=given))
            else:
                result.cases.append(CaseResult(case.label, [], error=out.error, seconds=out.seconds))
            continue
        try:
            verdicts = checks.verify(case, out.value, ref)
            if not all(v.passed for v in verdicts):
                given = _own_work(checks, case, out, seed)
                if given:
                    verdicts = [Verdict("own work", True)]
                    result.cases.append(CaseResult(case.label, verdicts, seconds=out.seconds, own_work_of=given))
                    continue
            result.cases.append(CaseResult(case.label, verdicts, seconds=out.seconds))
        except ShapeError as exc:
            given = _own_work(checks, case, out, seed)  # a callee's wrong shape can make the caller's wrong too
            verdicts = [Verdict("own work", True)] if given else [Verdict("output shape", False, str(exc))]
            result.cases.append(CaseResult(case.label, verdicts, seconds=out.seconds, own_work_of=given))
        except Exception as exc:  # noqa: BLE001 - unforeseen output the checks could not digest
            result.cases.append(
                CaseResult(case.label, [Verdict("readable output", False, f"{type(exc).__name__}: {exc}")], seconds=out.seconds)
            )
    return result


def wire(value: Any) -> Any:
    """What ``value`` looks like after the kernel → grader wire (see ``harness.kernel_side``)."""
    if sp.issparse(value):
        return sp.csr_matrix(value, dtype=float)
    if isinstance(value, (tuple, list)) and not all(isinstance(v, (int, float)) for v in value):
        return tuple(wire(v) for v in value)
    return np.array(value)


def seeded_cases(function: str, seed: int | tuple[int, ...] = 0, assignment: str | None = None) -> tuple[list[Case], list[Any]]:
    """The cases of ``function`` of ``assignment`` (default: the course's default) drawn with ``default_rng(seed)``,
    and the reference's outputs on them (cached per process)."""
    return _seeded_cases(pack(assignment).name, function, seed)


@functools.lru_cache(maxsize=128)
def _seeded_cases(assignment: str, function: str, seed: int | tuple[int, ...]) -> tuple[list[Case], list[Any]]:
    cases = all_checks(assignment)[function].cases(np.random.default_rng(seed))
    course = callees.course_callees(pack(assignment))
    outputs, reached = callees.trace(course, lambda: reference_outputs(cases, assignment))
    key = (assignment, function)
    _REACHED[key] = _REACHED.get(key, frozenset()) | reached
    return cases, outputs


def check_namespace(function: str, namespace: dict, seed: int = 0, assignment: str | None = None) -> FunctionResult:
    """Verdicts for the implementations in ``namespace`` (name -> function), run in this process.

    The outputs go through the same conversion as the kernel's wire, so the
    verdicts are those grading would give.
    """
    assignment = pack(assignment).name
    cases, expected = seeded_cases(function, seed, assignment)
    outputs = []
    for case in cases:
        try:
            outputs.append(CaseOutput(wire(run_steps(case, lambda n: namespace[n])), None, None))
        except Exception as exc:  # noqa: BLE001 - a failing implementation fails its case
            outputs.append(CaseOutput(None, f"{type(exc).__name__}: {exc}\n{traceback.format_exc(limit=2)}", None))
    return evaluate(all_checks(assignment)[function], cases, outputs, expected)


def run_hidden_checks(function: str, namespace: dict, seed: int = 0, assignment: str | None = None) -> FunctionResult | None:
    """Run the hidden checks of ``function`` against the functions in ``namespace``.

    Used by the instructor (source) notebooks; grading runs the same checks
    out of the student's process instead.

    Raises
    ------
    AssertionError
        Listing the failed cases.
    """
    assignment = pack(assignment).name
    checks = all_checks(assignment)[function]
    # A function whose cases call one defined later in the notebook (a precomputation graded
    # through the solve step that uses it) is checked at the first tests cell where everything it needs exists.
    pending = namespace.setdefault("__deformlab_pending_checks__", [])
    if any(n not in namespace for n in checks.needs):
        pending.append(function)
        return None
    for waiting in [f for f in pending if all(n in namespace for n in all_checks(assignment)[f].needs)]:
        pending.remove(waiting)
        run_hidden_checks(waiting, namespace, seed, assignment)
    result = check_namespace(function, namespace, seed, assignment)
    if result.fraction < 1.0:
        raise AssertionError(f"hidden checks of {function}: {result.summary()}")
    return result
