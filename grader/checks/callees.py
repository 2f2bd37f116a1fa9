"""A bug is charged once: judge a function with the student's own outputs of the course functions it calls.

When a student's function calls another graded function of theirs that is
wrong (a best-rotation fit taking its sign from ``det(S)``, say), the caller's
output is wrong although its own logic is right. The kernel records every call the
collected function makes to the other course functions (their arguments'
sketches and their outputs, ``grader.harness.kernel_side``); here the reference
reruns the hidden case with those outputs in place of its own
(:func:`own_work_output`). A case the plain verdicts fail then passes when the
student's output matches that rerun: the difference came from the callees,
which are graded where they are taught.

Nothing crosses into the kernel but the names to record and a seed: the rerun
happens here, on the grader's side, with trusted code. The reference's calls
between course functions go through module globals; :func:`install` wraps those
globals once per process so that, inside :func:`own_work_output` only (a
``ContextVar``, so threads never see each other's substitutions), a call whose
arguments match a recorded call returns the student's recorded output.
Where the reference computes a callee inline, the course pack's ``COMPOSITIONS``
write the caller as its contract defines it in terms of its callees.

What is the course's lives in its pack's ``checks`` package, read by :func:`course_callees`:
``BATCHED`` (name -> (the argument holding a stack of independent items, the
number of trailing axes of one item): recorded whole, matched item by item, so a
student who calls them once per vertex is matched as well as one who calls them
on the stack), ``ALIASES`` (private reference functions that compute a graded
function on input already checked: a substitution applies to them too) and
``COMPOSITIONS`` (caller -> (its definition in terms of the course functions it
calls, given an object whose attributes are those functions; those functions)).
"""

from __future__ import annotations

import contextvars
import functools
import inspect
import math
import sys
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import scipy.sparse as sp
from scipy.spatial import cKDTree

from grader.checks.base import Case, close, max_abs, run_steps
from grader.course_pack import Assignment
from grader.harness.kernel_side import __deformlab_sketch__ as sketch
from grader.harness.outputs import RecordedCall

#: Relative tolerance of a sketch match: arguments computed in another order agree to ~1e-13.
MATCH_TOL = 1e-7
#: How close a student's output must be to the rerun (relative to the rerun's largest entry).
OWN_WORK_TOL = 1e-6


@dataclass(frozen=True)
class CourseCallees:
    """An assignment's graded functions as the reruns see them."""

    assignment: Assignment
    batched: dict[str, tuple[str, int]]
    aliases: dict[str, str]
    compositions: dict[str, tuple[Callable, tuple[str, ...]]]

    def callees(self) -> "_Callees":
        return _Callees(self.assignment)

    def resolve(self, name: str) -> Callable:
        """A case step's function in a rerun: its composition where it has one, else the (substitutable) reference."""
        if name in self.compositions:
            return functools.partial(self.compositions[name][0], self.callees())
        return self.assignment.reference_function(name)


_COURSES: dict[tuple[str, str], CourseCallees] = {}


def course_callees(assignment: Assignment) -> CourseCallees:
    """The pack's ``BATCHED``, ``ALIASES`` and ``COMPOSITIONS`` (empty where it declares none), its reference wrapped."""
    key = (assignment.name, str(assignment.folder))
    if key not in _COURSES:
        checks = assignment.checks_module()
        course = CourseCallees(
            assignment,
            dict(getattr(checks, "BATCHED", {})),
            dict(getattr(checks, "ALIASES", {})),
            dict(getattr(checks, "COMPOSITIONS", {})),
        )
        _install(course)
        _COURSES[key] = course
    return _COURSES[key]


_REPLAY: contextvars.ContextVar["_Replay | None"] = contextvars.ContextVar("deformlab_replay", default=None)


class _Substitutable:
    """A reference function whose calls a replay may answer with a student's recorded output."""

    def __init__(self, name: str, fn: Callable):
        functools.update_wrapper(self, fn)
        self.name = name
        self.fn = fn

    def __call__(self, *args, **kwargs):
        replay = _REPLAY.get()
        if replay is None:
            return self.fn(*args, **kwargs)
        return replay.call(self.name, self.fn, args, kwargs)


def _install(course: CourseCallees) -> None:
    """Wrap, once per process, every module global of the reference package that is a graded function (or an alias)."""
    assignment = course.assignment
    assignment.reference_modules()  # imported, so that every module to wrap is in sys.modules
    root = assignment.reference
    for modname, module in list(sys.modules.items()):
        if module is None or not (modname == root or modname.startswith(root + ".")):
            continue
        for attr, value in list(vars(module).items()):
            name = attr if attr in assignment.function_names else course.aliases.get(attr)
            if name is not None and inspect.isfunction(value):
                setattr(module, attr, _Substitutable(name, value))


def _sketch_matches(ours: dict, theirs: dict) -> bool:
    if ours.get("opaque") or theirs.get("opaque"):
        return True
    if "v" in ours or "v" in theirs:
        return "v" in ours and "v" in theirs and ours["v"] == theirs["v"]
    if ours["shape"] != theirs["shape"]:
        return False
    # the projections bound the scale too: a norm can underflow where they do not
    scale = max(ours["norm"], theirs["norm"], *map(abs, ours["p"]), *map(abs, theirs["p"]))
    if abs(ours["norm"] - theirs["norm"]) > MATCH_TOL * scale:
        return False
    return all(abs(a - b) <= 10 * MATCH_TOL * scale for a, b in zip(ours["p"], theirs["p"]))


def _bound(fn: Callable, args: tuple, kwargs: dict) -> dict | None:
    """Parameter name -> value of a call, defaults filled in; None if the call does not fit ``fn``."""
    try:
        bound = inspect.signature(fn).bind(*args, **kwargs)
    except TypeError:
        return None
    bound.apply_defaults()
    return dict(bound.arguments)


def _bound_sketches(fn: Callable, call: "RecordedCall", seed: int) -> dict | None:
    """Parameter name -> sketch of a recorded call's arguments, the defaults it left out sketched here."""
    try:
        bound = inspect.signature(fn).bind(*call.args, **call.kwargs)
    except TypeError:
        return None
    passed = dict(bound.arguments)
    return {
        p.name: passed[p.name] if p.name in passed else sketch(p.default, seed)
        for p in inspect.signature(fn).parameters.values()
    }


def pure(fn: Callable, args: tuple, kwargs: dict) -> Any:
    """The reference's own output, no substitution inside."""
    token = _REPLAY.set(None)
    try:
        return fn(*args, **kwargs)
    finally:
        _REPLAY.reset(token)


def _same_output(a: Any, b: Any) -> bool:
    """Whether two outputs agree to ``OWN_WORK_TOL`` (tuples item by item; sparse and dense alike)."""
    if isinstance(a, tuple) or isinstance(b, tuple):
        return isinstance(a, tuple) and isinstance(b, tuple) and len(a) == len(b) and all(map(_same_output, a, b))
    try:
        if sp.issparse(a) or sp.issparse(b):
            if a.shape != b.shape:
                return False
        else:
            a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
            if a.shape != b.shape:
                return False
            if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
                return False
        return close(a, b, OWN_WORK_TOL, max_abs(b))[0]
    except (TypeError, ValueError, AttributeError):
        return False


@dataclass
class _Replay:
    """The recorded calls of one case, answering the reference's calls that match them."""

    course: CourseCallees
    caller: str
    calls: list[RecordedCall]
    seed: int
    substituted: set[str] = field(default_factory=set)  # callees whose student output differed from the reference's
    _trees: dict = field(default_factory=dict)
    _composing: set = field(default_factory=set)

    def call(self, name: str, fn: Callable, args: tuple, kwargs: dict):
        if name == self.caller:
            return fn(*args, **kwargs)
        if name in self.course.batched:
            return self._batched(name, fn, args, kwargs)
        ours = _bound(fn, args, kwargs)
        if ours is not None:
            ours = {p: sketch(v, self.seed) for p, v in ours.items()}
            for call in self.calls:
                if call.name != name or call.args is None:
                    continue
                theirs = _bound_sketches(fn, call, self.seed)
                if theirs is not None and theirs.keys() == ours.keys() and all(
                    _sketch_matches(ours[p], theirs[p]) for p in ours
                ):
                    # whether the student's output differs: asked once per callee, a reference run each time
                    if name not in self.substituted and not _same_output(call.output, pure(fn, args, kwargs)):
                        self.substituted.add(name)
                    return call.output
        # not called on these arguments (or not readable, as a precomputation object): the reference's
        # own, as the caller's contract defines it in terms of the callees that may be substituted
        compositions = self.course.compositions
        if name in compositions and name not in self._composing:  # a composition may call its own reference
            self._composing.add(name)
            try:
                return compositions[name][0](self.course.callees(), *args, **kwargs)
            finally:
                self._composing.discard(name)
        return fn(*args, **kwargs)

    def _batched(self, name: str, fn: Callable, args: tuple, kwargs: dict):
        param, item_axes = self.course.batched[name]
        bound = _bound(fn, args, kwargs)
        reference = pure(fn, args, kwargs)
        if bound is None:
            return reference
        query = np.asarray(bound[param], dtype=float)
        item_shape = query.shape[query.ndim - item_axes:]
        tree, outputs = self._tree(name, item_shape)
        if tree is None:
            return reference
        flat = query.reshape(-1, math.prod(item_shape))
        distance, nearest = tree.query(flat)
        scale = np.maximum(np.linalg.norm(flat, axis=1), np.finfo(float).tiny)
        hit = np.isfinite(distance) & (distance <= MATCH_TOL * scale)
        if not hit.any():
            return reference
        result = np.array(reference, dtype=float).reshape(len(flat), -1)
        result[hit] = outputs[nearest[hit]]
        if not np.allclose(result, np.asarray(reference, dtype=float).reshape(len(flat), -1), rtol=0, atol=OWN_WORK_TOL):
            self.substituted.add(name)
        return result.reshape(np.shape(reference))

    def _tree(self, name: str, item_shape: tuple):
        """A k-d tree of every recorded item of ``name`` with this shape, and their outputs in its order."""
        key = (name, item_shape)
        if key not in self._trees:
            size = math.prod(item_shape)
            inputs, outputs = [], []
            for call in self.calls:
                if call.name != name or call.items is None or call.items.shape[call.items.ndim - len(item_shape):] != item_shape:
                    continue
                out = call.output
                if not isinstance(out, np.ndarray) or out.size != call.items.size:
                    continue
                inputs.append(call.items.reshape(-1, size))
                outputs.append(out.reshape(-1, size))
            if inputs:
                X = np.concatenate(inputs)
                keep = np.all(np.isfinite(X), axis=1)
                self._trees[key] = (cKDTree(X[keep]), np.concatenate(outputs)[keep])
            else:
                self._trees[key] = (None, None)
        return self._trees[key]


class _Callees:
    """``f.name(...)`` in a composition: the course function ``name``, substitutable."""

    def __init__(self, assignment: Assignment):
        self._assignment = assignment

    def __getattr__(self, name: str) -> Callable:
        return self._assignment.reference_function(name)


def recorded_names(course: CourseCallees, function: str, reached: frozenset[str]) -> list[str]:
    """The course functions to record while ``function`` is collected: what its rerun may call, less itself.

    ``reached`` are the course functions the reference called on the hidden cases (the cases' own
    steps among them); what their compositions call may be substituted too.
    """
    names = set(reached)
    for name in {function} | set(reached):
        names |= set(course.compositions.get(name, (None, ()))[1])
    return sorted(names - {function})


def trace(course: CourseCallees, run: Callable[[], Any]) -> tuple[Any, frozenset[str]]:
    """``run()`` and the course functions the reference called inside it (the callees worth recording)."""
    tracer = _Tracer()
    token = _REPLAY.set(tracer)
    try:
        return run(), frozenset(tracer.reached)
    finally:
        _REPLAY.reset(token)


class _Tracer:
    def __init__(self):
        self.reached: set[str] = set()

    def call(self, name, fn, args, kwargs):
        self.reached.add(name)
        return fn(*args, **kwargs)


def own_work_output(
    course: CourseCallees, case: Case, calls: list[RecordedCall], caller: str, seed: int
) -> tuple[Any, set[str], str | None] | None:
    """The reference's output on ``case`` given the student's recorded callee outputs.

    Parameters
    ----------
    course : CourseCallees
        The assignment of ``caller`` (:func:`course_callees`).
    case : Case
        A hidden case of ``caller``.
    calls : list of RecordedCall
        What the student's ``caller`` called while the case ran.
    caller : str
        The function judged; its own calls to itself are never substituted.
    seed : int
        The sketches' seed of the run.

    Returns
    -------
    (output, substituted, raised) or None
        ``substituted`` names the callees whose student outputs differed from
        the reference's on the same input; ``raised``, the name of the
        ``ValueError`` class when the contract's function raises on them (a
        genus that the student's Euler characteristic makes no integer), and
        then ``output`` is None; None when the rerun fails otherwise (the
        student's callee outputs do not fit the reference's code).
    """
    replay = _Replay(course, caller, calls, seed)
    token = _REPLAY.set(replay)
    try:
        return run_steps(case, course.resolve), replay.substituted, None
    except ValueError as exc:  # what the contract says the function raises on such input
        return None, replay.substituted, type(exc).__name__
    except Exception:  # noqa: BLE001 - outputs the reference cannot digest: no second chance
        return None
    finally:
        _REPLAY.reset(token)


def matches_own_work(got: Any, rerun: Any) -> bool:
    """Whether the student's output is the rerun's, to ``OWN_WORK_TOL``."""
    return _same_output(got, rerun)
