"""One work unit: one student × one notebook, from file to verdicts.

``grade_unit`` is a pure function of a self-contained ``UnitSpec`` (the
submitted bytes, the instructor notebook's text, seed, assignment, limits: no
host paths) that returns a JSON-serializable dict, so it runs the same in a
process pool here or as a task on another machine of a Dask cluster
(``grader.pipeline.distributed``): the engine ships a ``UnitSpec`` and receives
the dict; recording stays in one process (``grader.pipeline.record``).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import re
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import nbformat

from grader.course_pack import pack
from grader.harness.fixtures import write_fixtures
from grader.paths import course_paths
from grader.harness.outputs import OutputError, read_outputs
from grader.pipeline.execute import Execution, ExecuteOptions, execute, prestart
from grader.pipeline.feedback import feedback_html
from grader.pipeline.guard import GraderLimitExceeded, grader_limits, peak_rss_bytes, reset_peak_rss
from grader.pipeline.neutralize import neutralize
from grader.pipeline.sanitize import Sanitized, sanitize
from grader.pipeline.read_submission import SubmissionError, parse_submission, read_submission_bytes
from grader.pipeline.verify import graded_cells, hidden_cases, recording, verify
from grader.sandbox.bwrap import DEFAULT_FILE_BYTES
from grader.report.digest import output_digest
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES
from grader.sandbox.kernel import SandboxedKernelManager
from grader.sandbox import spares
from grader.sandbox.workspace import Workspace, workspace


@dataclass
class UnitSpec:
    """Everything one work unit needs, all plain data (no host paths).

    Attributes
    ----------
    student_id : str
        Exactly as the submission folder is named.
    notebook : str
        File stem of the assignment's notebook, its stage (``NN_name``).
    submission : bytes or None
        The submitted file's content; None if the student submitted none or
        ``submission_error`` says why it was not read.
    source : str
        The instructor (source) notebook, as JSON text.
    seed : int
        Seed of the run's hidden inputs.
    submission_sha256 : str or None
        Hash of the submitted file (identifies it when a re-run reuses results).
    submission_error : str or None
        Why the submitted file was not shipped (too large, unreadable).
    disk_bytes : int
        Size of the student's workdir (a tmpfs where the grader may mount one).
    wall : float
        Seconds the whole notebook may run, replays after kernel restarts included.
    """

    student_id: str
    notebook: str
    submission: bytes | None
    source: str
    seed: int
    assignment: str | None = None  # None: the course's default assignment
    timeout: float = 60.0
    memory_bytes: int = 4 * 2**30
    max_processes: int | None = DEFAULT_MAX_PROCESSES
    notes: list[str] = field(default_factory=list)
    submission_sha256: str | None = None
    submission_error: str | None = None
    disk_bytes: int = DEFAULT_FILE_BYTES
    wall: float = 900.0


def load_submission(path: str | Path | None) -> tuple[bytes | None, str | None, str | None]:
    """``(content, sha256, error)`` of a submitted file, read where the submissions are (the recording host).

    The file is the student's: it is read without following links, only if it
    is a regular file within ``MAX_NOTEBOOK_BYTES``; ``error`` says why not.
    """
    if path is None:
        return None, None, None
    try:
        content = read_submission_bytes(Path(path))
    except SubmissionError as exc:
        return None, None, str(exc)
    return content, hashlib.sha256(content).hexdigest(), None


def course_readonly() -> list[str]:
    """What a kernel may read of this machine's course kit: ``data/`` and the ``starter/`` package."""
    paths = course_paths()
    return [str(paths.data), str(paths.starter)]


def zero_result(spec: UnitSpec, source: nbformat.NotebookNode, status: str, reason: str, started: float) -> dict:
    """A result scoring 0 on every graded cell, with the reason."""
    tests = [
        {"grade_id": c.grade_id, "function": c.function, "points": c.points, "score": 0.0, "summary": reason, "cases": []}
        for c in graded_cells(source)
    ]
    return _result(spec, status, tests, [reason], started)


def _result(spec: UnitSpec, status: str, tests: list[dict], reasons: list[str], started: float, **extra) -> dict:
    return {
        "student_id": spec.student_id,
        "assignment": spec.assignment,
        "notebook": spec.notebook,
        "status": status,
        "score": round(sum(t["score"] for t in tests), 4),
        "max_score": sum(t["points"] for t in tests),
        "tests": tests,
        "reasons": reasons,
        "seed": spec.seed,
        "submission_sha256": spec.submission_sha256,
        "duration_s": round(time.monotonic() - started, 3),
        "grader_peak_rss_bytes": peak_rss_bytes(),  # the grading process's own peak over this unit
        **extra,
    }


@dataclass
class Unit:
    """What one unit's steps pass along, as nbgrader's preprocessors pass ``(nb, resources)``.

    Each step reads what earlier ones left and adds its own part; a step that
    ends the unit early (nothing to grade, an invalid file) sets ``result``.

    Attributes
    ----------
    spec : UnitSpec
    readonly : list of str
        Host paths the kernel may read.
    started : float
        ``time.monotonic()`` when the unit began.
    source : NotebookNode
        The instructor notebook.
    sanitized : Sanitized or None
        The submission rebuilt on the source's cells (:func:`grader.pipeline.sanitize.sanitize`).
    ws : Workspace or None
        The unit's sandbox folder, for the steps that run inside it.
    kernel : SandboxedKernelManager or None
        A kernel launched ahead of time in ``ws``, for the first kernel life.
    broken : dict of str to str
        Functions whose hidden inputs the grader could not prepare, and why (they score 0).
    run : Execution or None
        What executing the notebook and collecting the outputs gave.
    tests : list of dict
        One row per graded function (``grades.csv``'s tests).
    verified : list of tuple
        ``(GradedCell, FunctionResult, Collected or None)`` per function, for the feedback page.
    notes : list of str
        Shown to the student on the feedback page, before the reasons and events.
    result : dict or None
        The unit's result once it is decided.
    """

    spec: UnitSpec
    readonly: list[str]
    started: float
    source: nbformat.NotebookNode
    sanitized: Sanitized | None = None
    ws: Workspace | None = None
    kernel: SandboxedKernelManager | None = None
    broken: dict[str, str] = field(default_factory=dict)
    run: Execution | None = None
    tests: list[dict] = field(default_factory=list)
    verified: list[tuple] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    result: dict | None = None

    @functools.cached_property
    def cells(self) -> list:
        """The source's graded cells (:class:`grader.pipeline.verify.GradedCell`), in notebook order."""
        return graded_cells(self.source)


#: A step of a unit: reads and extends the :class:`Unit`; sets ``unit.result`` to end it early.
Step = Callable[[Unit], None]


def read(unit: Unit) -> None:
    """Step 1: end the unit if no notebook was handed in or the file could not be read."""
    spec = unit.spec
    if spec.submission_error is not None:
        unit.result = _ungraded(unit, "invalid", spec.submission_error)
    elif spec.submission is None:
        unit.result = _ungraded(unit, "missing", f"no {spec.notebook}.ipynb was submitted",
                                shown=f"No {spec.notebook}.ipynb was submitted.")


def sanitize_submission(unit: Unit) -> None:
    """Step 2: rebuild the submission on the source's cells (:mod:`grader.pipeline.sanitize`)."""
    try:
        unit.sanitized = sanitize(parse_submission(unit.spec.submission), unit.source)
    except SubmissionError as exc:
        unit.result = _ungraded(unit, "invalid", str(exc))


def prepare_inputs(unit: Unit) -> None:
    """Step 3, in the sandbox's folder: write each graded function's hidden inputs for the kernel."""
    spec = unit.spec
    for cell in unit.cells:
        try:
            write_fixtures(cell.function, hidden_cases(cell.function, spec.seed, spec.assignment)[0], unit.ws.work / "fixtures",
                           recording(cell.function, spec.seed, spec.assignment))
        except Exception as exc:  # noqa: BLE001 - costs this function, not the notebook
            unit.broken[cell.function] = f"grader error preparing hidden cases: {type(exc).__name__}: {exc}"


def execute_notebook(unit: Unit) -> None:
    """Step 4: run the notebook and collect each function's outputs in the sandbox (:mod:`grader.pipeline.execute`)."""
    spec, workdir = unit.spec, unit.ws.work
    (workdir / "outputs").mkdir()
    (workdir / f"{spec.notebook}.ipynb").write_text(_notebook_json(unit.sanitized.nb), encoding="utf-8")
    unit.run = execute(
        unit.sanitized.nb,
        unit.sanitized.plan,
        [c.function for c in unit.cells if c.function not in unit.broken],
        workdir,
        workdir / "fixtures",
        workdir / "outputs",
        _execute_options(spec, unit.readonly, unit.ws),
        kernel=unit.kernel,
    )
    pool = spares.pool()  # open in grading workers (grader.pipeline.workers)
    if pool is not None:  # the student's kernel is gone: the next unit's boots while this one is verified
        _prestart_next(pool, spec, unit.readonly)


def verify_outputs(unit: Unit) -> None:
    """Step 5: judge each function's collected outputs against the reference (:mod:`grader.pipeline.verify`)."""
    spec, nb, run = unit.spec, unit.sanitized.nb, unit.run
    failed_defs = {fn: i for i, _ in run.cell_failures.items() for fn in _defined(nb.cells[i])}
    outputs = unit.ws.work / "outputs"
    for cell in unit.cells:
        if cell.function in unit.broken:
            unit.tests.append({"grade_id": cell.grade_id, "function": cell.function, "points": cell.points,
                               "score": 0.0, "summary": unit.broken[cell.function], "cases": []})
            continue
        result, collected = _verified(cell.function, spec.seed, outputs, run.collection_failures.get(cell.function), spec.assignment)
        if cell.function in failed_defs and result.cases and all(
                (c.error or "").startswith(f"NameError: {cell.function} is not defined") for c in result.cases):
            # Its defining cell failed (a syntax error, say): say so, not "NameError".
            i = failed_defs[cell.function]
            result = verify(cell.function, spec.seed, None,
                            f"{cell.function} was never defined: {_cell_name(nb.cells[i])} failed with "
                            f"{run.cell_failures[i]}", spec.assignment)
            collected = None
        # Pictures only where a case failed: a passing function's picture tells its student
        # nothing new, and drawing it cost as much CPU as the rest of the unit.
        unit.verified.append((cell, result, collected if result.fraction < 1 else None))
        unit.tests.append(
            {
                "grade_id": cell.grade_id,
                "function": cell.function,
                "points": cell.points,
                "score": round(cell.points * result.fraction, 4),
                "summary": result.summary(),
                "policy_violations": list(result.policy_violations),
                "cases": [
                    {
                        "label": c.label,
                        "passed": c.passed,
                        "error": c.error,
                        "seconds": c.seconds,
                        "failed": [f"{v.name}: {v.detail}" for v in c.verdicts if not v.passed],
                        # Wrong outputs only: identical ones across students are collusion evidence (grader/report/collusion.py).
                        "digest": _wrong_output_digest(c, collected, k),
                    }
                    for k, c in enumerate(result.cases)
                ],
            }
        )
    pool = spares.pool()
    if pool is not None:  # its sandbox was built while this unit was verified; its kernel boots now
        pool.complete_launch()


def neutralize_outputs(unit: Unit) -> None:
    """Step 6: make the executed notebook inert for a TA's browser (:mod:`grader.pipeline.neutralize`)."""
    unit.notes = unit.spec.notes + unit.sanitized.notes + neutralize(unit.sanitized.nb, unit.source) + unit.notes


def render_feedback(unit: Unit) -> None:
    """Step 7: the student's feedback page and the unit's result (:mod:`grader.pipeline.feedback`)."""
    spec, nb, run = unit.spec, unit.sanitized.nb, unit.run
    reasons = [f"{_cell_name(nb.cells[i])}: {why}" for i, why in sorted(run.cell_failures.items())]
    status = "grader-error" if unit.broken else "graded" if not run.events else "graded-with-incidents"
    reasons += list(unit.broken.values())
    messages = unit.notes + reasons + run.events
    try:
        with grader_limits():
            feedback = feedback_html(spec, unit.verified, messages)
    except (GraderLimitExceeded, MemoryError):
        feedback = feedback_html(spec, [], [*messages, "Your outputs were too large or slow to draw; the scores above stand."])
    unit.result = _result(
        spec,
        status,
        unit.tests,
        reasons,
        unit.started,
        notes=unit.notes,
        events=run.events,
        peak_rss_bytes=run.peak_rss_bytes,
        execution_s=round(run.seconds, 3),
        feedback_html=feedback,
        autograded_notebook=_notebook_json(nb),
    )


#: The steps before a unit gets a sandbox, and those inside it, in order.
ON_HOST: tuple[Step, ...] = (read, sanitize_submission)
IN_SANDBOX: tuple[Step, ...] = (prepare_inputs, execute_notebook, verify_outputs)
#: After verification: a course pack's own steps (``[grading] steps``), then these.
FINISH: tuple[Step, ...] = (neutralize_outputs, render_feedback)


def unit_steps(assignment: str | None) -> tuple[tuple[Step, ...], tuple[Step, ...]]:
    """``(on the host, in the sandbox)``: the steps of a unit of ``assignment``, its course pack's own included.

    A course pack's steps (``[grading] steps`` in its assignment.toml) run after verification,
    before the feedback page: they see every verdict and may add notes for the student.
    """
    return ON_HOST, IN_SANDBOX + pack(assignment).grading_steps() + FINISH


def grade_unit(spec: UnitSpec, readonly: list[str] | None = None) -> dict:
    """Grade one submitted notebook: its steps (:func:`unit_steps`), in order. Never raises for anything the student did.

    Parameters
    ----------
    spec : UnitSpec
    readonly : list of str, optional
        Host paths the kernel may read (the course's ``data/`` and ``starter/``);
        default: those of the course kit on the machine that runs the unit.

    Returns
    -------
    dict
        ``student_id, assignment, notebook, status, score, max_score, tests,
        reasons, seed, duration_s, peak_rss_bytes, events, feedback_html,
        autograded_notebook`` (the executed notebook as JSON text, or None).
    """
    started = time.monotonic()
    reset_peak_rss()
    unit = Unit(spec, [], started, nbformat.reads(spec.source, as_version=4))
    try:
        on_host, in_sandbox = unit_steps(spec.assignment)
        for step in on_host:
            step(unit)
            if unit.result is not None:
                return unit.result
        unit.readonly = course_readonly() if readonly is None else readonly
        with _sandbox(spec, unit.readonly) as (unit.ws, unit.kernel):
            for step in in_sandbox:
                step(unit)
                if unit.result is not None:
                    return unit.result
        raise RuntimeError(f"no step of {spec.assignment}'s grading gave the unit a result")
    except Exception as exc:  # noqa: BLE001 - the grader's own failure on this unit: this row says so, the run goes on
        return _grader_error(spec, unit.source, exc, started)


def _sandbox_key(spec: UnitSpec, readonly: list[str]) -> tuple:
    """What a pre-started sandbox was made for: the unit's limits and the course paths it may read."""
    return (spec.disk_bytes, spec.memory_bytes, spec.max_processes, tuple(map(str, readonly)))


@contextlib.contextmanager
def _sandbox(spec: UnitSpec, readonly: list[str]):
    """``(workspace, kernel or None)`` for one unit: the spare started for it, else a new workspace."""
    pool = spares.pool()
    spare = pool.take(_sandbox_key(spec, readonly)) if pool is not None else None
    if spare is None:
        with workspace(spec.disk_bytes) as ws:
            yield ws, None
        return
    try:
        yield spare.ws, spare.km
    finally:
        spare.close()  # execute shut the kernel down already, unless the unit failed before it ran


def _prestart_next(pool: spares.SparePool, spec: UnitSpec, readonly: list[str]) -> None:
    """Launch the sandbox of this thread's next unit, assuming it has ``spec``'s limits (a class's units do)."""
    pool.launch(_sandbox_key(spec, readonly), spec.disk_bytes, lambda ws: prestart(ws.work, _execute_options(spec, readonly, ws)))


def _execute_options(spec: UnitSpec, readonly: list[str], ws: Workspace) -> ExecuteOptions:
    return ExecuteOptions(
        timeout=spec.timeout,
        wall=spec.wall,
        memory_bytes=spec.memory_bytes,
        max_processes=spec.max_processes,
        readonly=[Path(p) for p in readonly],
        runtime_root=ws.kernels,
    )


_DEF = re.compile(r"^def\s+(\w+)\s*\(", re.M)


def _defined(cell) -> list[str]:
    """The functions a code cell defines at top level (read from its text: a cell with a syntax error has no AST)."""
    return _DEF.findall(cell.get("source", "")) if cell.get("cell_type") == "code" else []


def _cell_name(cell) -> str:
    """A cell as a student finds it in JupyterLab, which shows no cell numbers: by what it defines, else its first line."""
    defined = _defined(cell)
    if defined:
        return "the cell defining " + ", ".join(f"{fn}()" for fn in defined)
    first = next((line.strip() for line in cell.get("source", "").splitlines() if line.strip()), "")
    return f'the cell starting "{first[:60]}{"…" if len(first) > 60 else ""}"'


def _notebook_json(nb: nbformat.NotebookNode) -> str:
    """The notebook as JSON text, compact.

    ``nbformat.writes`` indents, which sends ``json`` to its pure-Python encoder, and re-validates
    a notebook ``sanitize`` built from validated cells: about 30 ms of each unit's CPU. Any JSON
    reader (nbformat, formgrader) reads this the same.
    """
    return json.dumps(nb, ensure_ascii=False)


def _verified(function: str, seed: int, outputs: Path, failure: str | None, assignment: str | None = None):
    """Read one function's outputs and judge them, under the grader's own limits.

    Returns
    -------
    (FunctionResult, Collected or None)
    """
    collected = None
    try:
        with grader_limits():
            if failure is None:
                cases, expected = hidden_cases(function, seed, assignment)
                try:
                    collected = read_outputs(function, outputs, len(cases), expected)
                except OutputError as exc:
                    failure = str(exc)
            return verify(function, seed, collected, failure, assignment), collected
    except (GraderLimitExceeded, MemoryError) as exc:
        why = "took too long" if isinstance(exc, GraderLimitExceeded) else "needed too much memory"
        return verify(function, seed, None, f"checking these outputs {why} (the grader's own limits); they score 0", assignment), None


def _wrong_output_digest(case, collected, k: int) -> str | None:
    if case.passed or collected is None or k >= len(collected.cases) or collected.cases[k].error is not None:
        return None
    return output_digest(collected.cases[k].value) or None


def _ungraded(unit: Unit, status: str, reason: str, shown: str | None = None) -> dict:
    """Zero on every cell, the reason and the planning's notes on the feedback page, no executed notebook."""
    spec = unit.spec
    return zero_result(spec, unit.source, status, reason, unit.started) | {
        "notes": list(spec.notes),
        "feedback_html": feedback_html(spec, [], [shown or reason, *spec.notes]),
        "autograded_notebook": None,
    }


def _grader_error(spec: UnitSpec, source: nbformat.NotebookNode, exc: BaseException, started: float) -> dict:
    return zero_result(spec, source, "grader-error", f"grader error: {type(exc).__name__}: {exc}", started) | {
        "feedback_html": feedback_html(spec, [], ["The grader failed on this notebook; your TA has been told."]),
        "autograded_notebook": None,
        "traceback": traceback.format_exc(),
    }
