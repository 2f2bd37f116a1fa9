"""``deformlab grade``: a class of submissions through the pipeline, in parallel.

sanitize → execute in a sandbox → collect → verify run inside each work unit
(``grader.pipeline.unit``). This module prepares a run (instructor notebooks,
gradebook, the output folder's lock, the run's seed, what an earlier run into
the same folder already graded), has the units planned (``grader.pipeline.plan``)
and graded in a local process pool (``grader.pipeline.local_pool``) or on a Dask
cluster (``grader.pipeline.distributed``), and records each result as it
arrives, in this one process (``grader.pipeline.record``).
"""

from __future__ import annotations

import dataclasses

import fcntl
import json
import os
import secrets
import sys
import time
from pathlib import Path

import nbformat

from grader.course_pack import default_assignment, pack
from grader.paths import CoursePaths, course_paths
from grader.pipeline import record
from grader.pipeline.local_pool import grade_in_pool
from grader.pipeline.options import GradeOptions
from grader.pipeline.plan import PlannedUnit, plan_units, unit_spec
from grader.pipeline.submitted import check_submitted
from grader.pipeline.unit import UnitSpec, grade_unit, load_submission, zero_result
from grader.sandbox.process_limit import remove_stale_limits
from grader.sandbox.workspace import remove_stale_workspaces


def ensure_sources(paths: CoursePaths, assignment: str) -> list[Path]:
    """The instructor notebooks, built from notebooks/ + reference/ if missing."""
    sources = paths.source_notebooks(assignment)
    if not sources:
        from grader.build.source_notebook import build_sources

        sources = build_sources(paths.source, assignment)
    return sources


def ensure_gradebook(paths: CoursePaths, db_url: str, assignment: str) -> None:
    """Make sure the gradebook knows the assignment (nbgrader's own generate_assignment does that).

    Two runs starting at once on one course (two TAs, one database) take turns:
    a lock file in the course folder serializes them on this host, and a run
    on another host that loses the race finds the assignment on its retry.
    """
    from nbgrader.api import MissingEntry

    def known() -> bool:
        with record.open_gradebook(db_url) as gb:
            try:
                gb.find_assignment(assignment)
                return True
            except MissingEntry:
                return False

    paths.course.mkdir(parents=True, exist_ok=True)
    with open(paths.course / ".deformlab-gradebook.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if known():
            return
        from grader.gradebook import GradebookError, generate_assignment

        try:
            generate_assignment(paths, assignment, db_url)
        except GradebookError:
            if not known():
                raise


def _known_students(db_url: str) -> list[str]:
    with record.open_gradebook(db_url) as gb:
        return [s.id for s in gb.students]


class GradingInProgress(RuntimeError):
    """Another grading run is writing into the same output folder."""


def _lock_out(out: Path):
    """Hold ``OUT/.grading.lock`` for the run: two runs into one OUT would write its files twice."""
    handle = open(out / ".grading.lock", "w")  # noqa: SIM115 - held until grade_class returns
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        handle.close()
        raise GradingInProgress(f"another `deformlab grade` is writing into {out}; wait for it or choose another --out") from None
    return handle


def _run_seed(out: Path, requested: int | None) -> int:
    """A fresh seed per run, kept in ``OUT/run.json`` so re-running the same OUT is idempotent."""
    run_file = out / "run.json"
    if requested is None and run_file.is_file():
        try:
            return int(json.loads(run_file.read_text())["seed"])
        except (ValueError, KeyError, TypeError):
            pass
    seed = requested if requested is not None else secrets.randbits(32)
    record.write_text_atomic(run_file, json.dumps({"seed": seed}))
    return seed


def _reusable(out: Path, unit: PlannedUnit, seed: int) -> dict | None:
    previous = record.load_unit(out, unit.student_id, unit.notebook)
    if (
        previous
        and previous.get("seed") == seed
        and previous.get("submission_sha256") == load_submission(unit.submission)[1]
        and previous.get("status") != "grader-error"
    ):
        return previous | {"reused": True}
    return None


def grade_class(submitted: Path, out: Path, options: GradeOptions, paths: CoursePaths | None = None, grade=grade_unit) -> list[dict]:
    """Grade every student × notebook under ``submitted``; write ``out``.

    ``paths`` selects the course (its source notebooks, data/ and starter/);
    default: the configured course (``grader.paths.course_paths``). Units run
    in a local process pool, or on a Dask cluster when ``options.scheduler``
    is set; either way this process records each result as it arrives. ``grade`` is the work unit of the
    process pool (``grade_unit``; tests pass a picklable stand-in that makes a worker die).

    Returns
    -------
    list of dict
        One result per student × notebook (see ``grade_unit``).

    Raises
    ------
    FileNotFoundError
        If ``submitted`` is not a folder.
    GradingInProgress
        If another run is writing into ``out``.
    ValueError
        If ``options.scheduler`` is malformed or names no reachable cluster.
    """
    submitted, out = Path(submitted), Path(out)
    if not submitted.is_dir():
        raise FileNotFoundError(f"SUBMITTED must be a folder of student folders: {submitted} is not a folder")
    if options.assignment is None:
        options = dataclasses.replace(options, assignment=default_assignment())
    # planned before anything is built or written: a wrong folder or assignment is refused at once
    pack(options.assignment)
    check_submitted(submitted, options.assignment)
    if options.scheduler:
        from grader.pipeline.distributed import parse_scheduler

        parse_scheduler(options.scheduler)  # a typo fails before anything is written
    out.mkdir(parents=True, exist_ok=True)
    with _lock_out(out):
        return _grade_class(submitted, out, options, paths, grade)


def _grade_class(submitted: Path, out: Path, options: GradeOptions, paths: CoursePaths | None, grade) -> list[dict]:
    # What graders killed mid-unit left behind: work folders (hidden inputs) and cgroups.
    remove_stale_workspaces()
    remove_stale_limits()
    paths = paths or course_paths()
    db_url = options.db_url or paths.gradebook_url
    sources = ensure_sources(paths, options.assignment)
    ensure_gradebook(paths, db_url, options.assignment)
    seed = _run_seed(out, options.seed)
    units = plan_units(submitted, sources, options, _known_students(db_url))
    source_texts = {s: s.read_text(encoding="utf-8") for s in sources}
    from grader.sandbox import bwrap_available

    if not options.scheduler and not bwrap_available():
        print("warning: bubblewrap not available: grading without filesystem/network isolation", file=sys.stderr)

    reused: list[tuple[PlannedUnit, dict]] = []
    todo = []
    if options.student is not None and options.student not in {u.student_id for u in units}:
        raise ValueError(f"--student {options.student!r}: no such student in {submitted} or the gradebook")
    for unit in units:
        if options.student is not None and unit.student_id != options.student:
            previous = record.load_unit(out, unit.student_id, unit.notebook)
            if previous is None:
                raise ValueError(f"--student regrades one student of an earlier run into {out}, which has no result for {unit.student_id} {unit.notebook}")
            reused.append((unit, previous | {"reused": True}))
            continue
        previous = None if options.student is not None else _reusable(out, unit, seed)
        if previous:
            reused.append((unit, previous))
        else:
            todo.append(unit)
    results = [r for _, r in reused]

    from tqdm import tqdm

    def spec_of(unit: PlannedUnit) -> UnitSpec:
        return unit_spec(unit, seed, options, source_texts[unit.source])

    def error_of(unit: PlannedUnit, reason: str) -> dict:
        return _grader_error(spec_of(unit), reason)

    if options.scheduler:
        from grader.pipeline.distributed import grade_on_dask

        stream = grade_on_dask(todo, spec_of, error_of, options.scheduler, allow_unsandboxed=options.allow_unsandboxed)
    else:
        readonly = [str(paths.data), str(paths.starter)]
        stream = grade_in_pool(todo, spec_of, error_of, max(1, options.workers or os.cpu_count() or 1), readonly, grade)

    autograded = options.autograded or paths.course / "autograded"
    bar = tqdm(total=len(units), initial=len(results), desc="grading", unit="nb", disable=not options.progress, file=sys.stderr)
    with record.open_gradebook(db_url) as gb:
        for unit, r in reused:
            if unit.in_folder:
                record.record_gradebook(gb, r)
            record.append_log(out, r)
        for unit, result in stream:
            record_result(out, autograded, gb if unit.in_folder else None, result)
            results.append(result)
            bar.update(1)
    bar.close()
    record.write_grades_csv(out, results)
    record.compact_log(out)
    _print_summary(results, out)
    return results


def _grader_error(spec: UnitSpec, reason: str) -> dict:
    source = nbformat.reads(spec.source, as_version=4)
    return zero_result(spec, source, "grader-error", reason, time.monotonic()) | {"feedback_html": None, "autograded_notebook": None}


def record_result(out: Path, autograded: Path, gb, result: dict) -> None:
    """Record one unit: feedback page, executed notebook, gradebook (unless ``gb`` is None), unit file, log line."""
    record.write_feedback(out, result)
    record.write_autograded(autograded, result)
    if gb is not None:
        record.record_gradebook(gb, result)
    record.save_unit(out, result)
    record.append_log(out, result)


def _print_summary(results: list[dict], out: Path) -> None:
    by_status: dict[str, int] = {}
    for r in results:
        by_status[r["status"]] = by_status.get(r["status"], 0) + 1
    students = sorted({r["student_id"] for r in results})
    print(
        f"graded {len(results)} notebooks of {len(students)} students: "
        + ", ".join(f"{n} {s}" for s, n in sorted(by_status.items()))
    )
    print(f"grades: {out / 'grades.csv'}; feedback: {out / 'feedback'}; log: {out / 'log.jsonl'}")
