"""One work unit: one student × one notebook, from file to verdicts.

``grade_unit`` is a pure function of its inputs (paths, seed, options) that
returns a JSON-serializable dict, so it can run in a process pool here, or as a
task of a distributed engine (Dask, Ray, Celery) with the same code: the engine
ships a ``UnitSpec`` and receives the dict; recording stays in one place.
"""

from __future__ import annotations

import hashlib
import os
import stat
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

import nbformat

from grader.harness.fixtures import write_fixtures
from grader.harness.outputs import OutputError, read_outputs
from grader.pipeline.execute import ExecuteOptions, execute
from grader.pipeline.feedback import feedback_html
from grader.pipeline.guard import GraderLimitExceeded, grader_limits, peak_rss_bytes, reset_peak_rss
from grader.pipeline.neutralize import neutralize
from grader.pipeline.sanitize import SubmissionError, read_submission, sanitize
from grader.pipeline.verify import graded_cells, hidden_cases, verify
from grader.sandbox.bwrap import DEFAULT_FILE_BYTES
from grader.report.digest import output_digest
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES
from grader.sandbox.workspace import workspace


@dataclass
class UnitSpec:
    """Everything one work unit needs, all plain data.

    Attributes
    ----------
    student_id : str
        Exactly as the submission folder is named.
    notebook : str
        File stem of the assignment's notebook, e.g. ``03_arap``.
    submission : str or None
        Path of the submitted file; None if the student submitted none.
    source : str
        Path of the instructor (source) notebook.
    seed : int
        Seed of the run's hidden inputs.
    disk_bytes : int
        Size of the student's workdir (a tmpfs where the grader may mount one).
    wall : float
        Seconds the whole notebook may run, replays after kernel restarts included.
    """

    student_id: str
    notebook: str
    submission: str | None
    source: str
    seed: int
    assignment: str = "deformation"
    timeout: float = 60.0
    memory_bytes: int = 4 * 2**30
    max_processes: int | None = DEFAULT_MAX_PROCESSES
    readonly: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    disk_bytes: int = DEFAULT_FILE_BYTES
    wall: float = 900.0


def sha256_of(path: str | Path) -> str | None:
    """SHA-256 of a submitted file, read in chunks and never through a link; None if unreadable."""
    digest = hashlib.sha256()
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError:
        return None
    with os.fdopen(fd, "rb") as fh:
        if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):
            return None
        while chunk := fh.read(2**20):
            digest.update(chunk)
    return digest.hexdigest()


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
        "submission_sha256": sha256_of(spec.submission) if spec.submission else None,
        "duration_s": round(time.monotonic() - started, 3),
        "grader_peak_rss_bytes": peak_rss_bytes(),  # the grading process's own peak over this unit
        **extra,
    }


def grade_unit(spec: UnitSpec) -> dict:
    """Grade one submitted notebook. Never raises for anything the student did.

    Returns
    -------
    dict
        ``student_id, assignment, notebook, status, score, max_score, tests,
        reasons, seed, duration_s, peak_rss_bytes, events, feedback_html,
        autograded_notebook`` (the executed notebook as JSON text, or None).
    """
    started = time.monotonic()
    reset_peak_rss()
    source = nbformat.read(spec.source, as_version=4)
    if spec.submission is None:
        return zero_result(spec, source, "missing", f"no {spec.notebook}.ipynb was submitted", started) | {
            "feedback_html": feedback_html(spec, [], [f"No {spec.notebook}.ipynb was submitted."]),
            "autograded_notebook": None,
        }
    try:
        sanitized = sanitize(read_submission(Path(spec.submission)), source)
    except SubmissionError as exc:
        return zero_result(spec, source, "invalid", str(exc), started) | {
            "feedback_html": feedback_html(spec, [], [str(exc)]),
            "autograded_notebook": None,
        }
    except Exception as exc:  # noqa: BLE001 - the grader's own failure on this file: this row says so
        return _grader_error(spec, source, exc, started)

    cells = graded_cells(source)
    try:
        with workspace(spec.disk_bytes) as ws:
            return _grade_in(ws, spec, source, sanitized, cells, started)
    except Exception as exc:  # noqa: BLE001 - the grader's own failure: this row says so, the run goes on
        return _grader_error(spec, source, exc, started)


def _grade_in(ws, spec: UnitSpec, source, sanitized, cells, started: float) -> dict:
    """Steps 2–5 of one unit inside its workspace ``ws``."""
    workdir = ws.work
    fixtures, outputs = workdir / "fixtures", workdir / "outputs"
    outputs.mkdir()
    broken: dict[str, str] = {}  # functions whose hidden cases the reference itself failed on
    for cell in cells:
        try:
            write_fixtures(cell.function, hidden_cases(cell.function, spec.seed)[0], fixtures)
        except Exception as exc:  # noqa: BLE001 - costs this function, not the notebook
            broken[cell.function] = f"grader error preparing hidden cases: {type(exc).__name__}: {exc}"
    nbformat.write(sanitized.nb, workdir / f"{spec.notebook}.ipynb")
    run = execute(
        sanitized.nb,
        sanitized.plan,
        [c.function for c in cells if c.function not in broken],
        workdir,
        fixtures,
        outputs,
        ExecuteOptions(
            timeout=spec.timeout,
            wall=spec.wall,
            memory_bytes=spec.memory_bytes,
            max_processes=spec.max_processes,
            readonly=[Path(p) for p in spec.readonly],
            runtime_root=ws.kernels,
        ),
    )
    tests, results = [], []
    for cell in cells:
        if cell.function in broken:
            tests.append({"grade_id": cell.grade_id, "function": cell.function, "points": cell.points,
                          "score": 0.0, "summary": broken[cell.function], "cases": []})
            continue
        result, collected = _verified(cell.function, spec.seed, outputs, run.collection_failures.get(cell.function))
        results.append((cell, result, collected))
        tests.append(
            {
                "grade_id": cell.grade_id,
                "function": cell.function,
                "points": cell.points,
                "score": round(cell.points * result.fraction, 4),
                "summary": result.summary(),
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
    reasons = [f"cell {i + 1}: {why}" for i, why in sorted(run.cell_failures.items())]
    status = "grader-error" if broken else "graded" if not run.events else "graded-with-incidents"
    reasons += list(broken.values())
    notes = spec.notes + sanitized.notes + neutralize(sanitized.nb, source)  # nothing active reaches a TA's browser
    messages = notes + reasons + run.events
    try:
        with grader_limits():
            feedback = feedback_html(spec, results, messages)
    except (GraderLimitExceeded, MemoryError):
        feedback = feedback_html(spec, [], [*messages, "Your outputs were too large or slow to draw; the scores above stand."])
    return _result(
        spec,
        status,
        tests,
        reasons,
        started,
        notes=notes,
        events=run.events,
        peak_rss_bytes=run.peak_rss_bytes,
        execution_s=round(run.seconds, 3),
        feedback_html=feedback,
        autograded_notebook=nbformat.writes(sanitized.nb),
    )


def _verified(function: str, seed: int, outputs: Path, failure: str | None):
    """Read one function's outputs and judge them, under the grader's own limits.

    Returns
    -------
    (FunctionResult, Collected or None)
    """
    collected = None
    try:
        with grader_limits():
            if failure is None:
                cases, expected = hidden_cases(function, seed)
                try:
                    collected = read_outputs(function, outputs, len(cases), expected)
                except OutputError as exc:
                    failure = str(exc)
            return verify(function, seed, collected, failure), collected
    except (GraderLimitExceeded, MemoryError) as exc:
        why = "took too long" if isinstance(exc, GraderLimitExceeded) else "needed too much memory"
        return verify(function, seed, None, f"checking these outputs {why} (the grader's own limits); they score 0"), None


def _wrong_output_digest(case, collected, k: int) -> str | None:
    if case.passed or collected is None or k >= len(collected.cases) or collected.cases[k].error is not None:
        return None
    return output_digest(collected.cases[k].value) or None


def _grader_error(spec: UnitSpec, source: nbformat.NotebookNode, exc: BaseException, started: float) -> dict:
    return zero_result(spec, source, "grader-error", f"grader error: {type(exc).__name__}: {exc}", started) | {
        "feedback_html": feedback_html(spec, [], ["The grader failed on this notebook; your TA has been told."]),
        "autograded_notebook": None,
        "traceback": traceback.format_exc(),
    }
