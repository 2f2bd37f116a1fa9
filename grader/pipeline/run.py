"""``deformlab grade``: a class of submissions through the pipeline, in parallel.

sanitize → execute in a sandbox → collect → verify run inside each work unit
(``grader.pipeline.unit``); this module finds the units, runs them in a process
pool, and records each result as it arrives (``grader.pipeline.record``).
"""

from __future__ import annotations

import fcntl
import json
import multiprocessing
import os
import secrets
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path

import nbformat

from grader.contract import ASSIGNMENT
from grader.paths import CoursePaths, course_paths
from grader.pipeline import record
from grader.pipeline.sanitize import read_submission_bytes
from grader.pipeline.submitted import student_folders
from grader.pipeline.unit import UnitSpec, grade_unit, sha256_of, zero_result
from grader.sandbox.bwrap import DEFAULT_FILE_BYTES
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES, remove_stale_limits
from grader.sandbox.workspace import remove_stale_workspaces


@dataclass
class GradeOptions:
    workers: int | None = None
    timeout: float = 60.0
    memory_gb: float = 4.0
    max_processes: int = DEFAULT_MAX_PROCESSES
    db_url: str | None = None
    seed: int | None = None
    assignment: str = ASSIGNMENT
    progress: bool = True
    autograded: Path | None = None  # where executed notebooks go for formgrader; default: the course's autograded/
    wall: float = 900.0  # seconds per notebook
    disk_bytes: int = DEFAULT_FILE_BYTES  # each student's workdir
    student: str | None = None  # grade only this student again; the others' results are read from OUT as they are


def _worker_init() -> None:
    # Each worker is one of N parallel graders: one BLAS thread each keeps N cores busy, not N².
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"


def find_submission(folder: Path, notebook: str) -> tuple[Path | None, list[str]]:
    """The student's file for ``notebook``, also when renamed (matched by the notebook's own metadata).

    Every candidate is the student's: read without following links, within the
    notebook size cap, and whatever fails to parse (deep nesting included) is
    passed over; it never raises for a file's content.
    """
    exact = folder / f"{notebook}.ipynb"
    if exact.is_file() or exact.is_symlink():
        return exact, []
    if folder.is_dir() and not folder.is_symlink():
        for candidate in sorted(folder.glob("*.ipynb")):
            try:
                meta = json.loads(read_submission_bytes(candidate)).get("metadata", {})
                named = (meta.get("deformlab") or {}).get("notebook") if isinstance(meta, dict) else None
            except Exception:  # noqa: BLE001 - RecursionError, MemoryError, anything: not this notebook
                continue
            if named == notebook:
                return candidate, [f"graded {candidate.name} as {notebook}.ipynb (renamed file)"]
    return None, []


def ensure_sources(paths: CoursePaths, assignment: str) -> list[Path]:
    """The instructor notebooks, built from notebooks/ + reference/ if missing."""
    sources = paths.source_notebooks(assignment)
    if not sources:
        from grader.build.source_notebook import build_sources

        sources = build_sources(paths.notebooks, paths.source, assignment)
    return sources


def ensure_gradebook(paths: CoursePaths, db_url: str, assignment: str) -> None:
    """Make sure the gradebook knows the assignment (nbgrader's own generate_assignment does that)."""
    from nbgrader.api import Gradebook, MissingEntry

    with Gradebook(db_url) as gb:
        try:
            gb.find_assignment(assignment)
            return
        except MissingEntry:
            pass
    from grader.build.release import generate_assignment

    generate_assignment(paths, assignment, db_url)


def _known_students(db_url: str) -> list[str]:
    from nbgrader.api import Gradebook

    with Gradebook(db_url) as gb:
        return [s.id for s in gb.students]


def plan_units(submitted: Path, sources: list[Path], seed: int, options: GradeOptions, paths: CoursePaths, roster: list[str]) -> list[UnitSpec]:
    """One ``UnitSpec`` per student × notebook: students from the folder and from the gradebook's roster.

    A student folder that is a link is not followed (its student gets a row saying so).
    """
    folders = student_folders(submitted, options.assignment)
    units = []
    for sid in sorted(set(folders) | set(roster)):
        folder = folders.get(sid)
        for source in sources:
            notebook = source.stem
            notes: list[str] = []
            path = None
            if folder is None:
                notes.append("no submission folder for this student")
            elif folder.is_symlink():
                notes.append("the submission folder is a link, which is not followed")
            else:
                try:
                    path, notes = find_submission(folder / options.assignment, notebook)
                except OSError as exc:  # an unreadable folder costs its own student only
                    notes.append(f"cannot read the submission folder: {exc.strerror}")
            units.append(
                UnitSpec(
                    student_id=sid,
                    notebook=notebook,
                    submission=str(path) if path else None,
                    source=str(source),
                    seed=seed,
                    assignment=options.assignment,
                    timeout=options.timeout,
                    memory_bytes=int(options.memory_gb * 2**30),
                    max_processes=options.max_processes,
                    readonly=[str(paths.data), str(paths.starter)],
                    notes=notes,
                    wall=options.wall,
                    disk_bytes=options.disk_bytes,
                )
            )
    return units


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


def _reusable(out: Path, unit: UnitSpec) -> dict | None:
    previous = record.load_unit(out, unit.student_id, unit.notebook)
    if (
        previous
        and previous.get("seed") == unit.seed
        and previous.get("submission_sha256") == (sha256_of(unit.submission) if unit.submission else None)
        and previous.get("status") != "grader-error"
    ):
        return previous | {"reused": True}
    return None


def grade_class(submitted: Path, out: Path, options: GradeOptions, paths: CoursePaths | None = None, grade=grade_unit) -> list[dict]:
    """Grade every student × notebook under ``submitted``; write ``out``.

    ``paths`` selects the course (its source notebooks, data/ and starter/);
    default: this checkout. ``grade`` is the work unit (``grade_unit``; tests
    pass a picklable stand-in to make a worker die).

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
    """
    submitted, out = Path(submitted), Path(out)
    if not submitted.is_dir():
        raise FileNotFoundError(f"SUBMITTED must be a folder of student folders: {submitted} is not a folder")
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
    units = plan_units(submitted, sources, seed, options, paths, _known_students(db_url))
    from grader.sandbox import bwrap_available

    if not bwrap_available():
        print("warning: bubblewrap not available: grading without filesystem/network isolation", file=sys.stderr)

    results: list[dict] = []
    todo = []
    if options.student is not None and options.student not in {u.student_id for u in units}:
        raise ValueError(f"--student {options.student!r}: no such student in {submitted} or the gradebook")
    for unit in units:
        if options.student is not None and unit.student_id != options.student:
            previous = record.load_unit(out, unit.student_id, unit.notebook)
            if previous is None:
                raise ValueError(f"--student regrades one student of an earlier run into {out}, which has no result for {unit.student_id} {unit.notebook}")
            results.append(previous | {"reused": True})
            continue
        previous = None if options.student is not None else _reusable(out, unit)
        if previous:
            results.append(previous)
        else:
            todo.append(unit)

    from nbgrader.api import Gradebook
    from tqdm import tqdm

    autograded = options.autograded or paths.course / "autograded"
    workers = max(1, options.workers or os.cpu_count() or 1)
    bar = tqdm(total=len(units), initial=len(results), desc="grading", unit="nb", disable=not options.progress, file=sys.stderr)
    with Gradebook(db_url) as gb:
        for r in results:
            record.record_gradebook(gb, r)
            record.append_log(out, r)

        def finish(result: dict) -> None:
            _record(out, autograded, gb, result)
            results.append(result)
            bar.update(1)

        while todo:
            suspects = _grade_in_pool(todo, workers, grade, finish)
            # A grading worker died (not a kernel: those are handled inside the unit). Only a unit the
            # pool had handed out can have killed it: grade each of those alone, so that a culprit
            # breaks only its own pool and its neighbours keep their grades.
            for unit in suspects:
                todo.remove(unit)
                finish(_grade_alone(unit, grade))
            if suspects:
                remove_stale_workspaces()  # what the dead worker held (if older than a few seconds; else the next run)
                remove_stale_limits()
    bar.close()
    record.write_grades_csv(out, results)
    record.compact_log(out)
    _print_summary(results, out)
    return results


def _pool(workers: int) -> ProcessPoolExecutor:
    # spawn, not fork: a forked child inherits jupyter's event-loop thread as a dead handle and hangs.
    return ProcessPoolExecutor(max_workers=workers, initializer=_worker_init, mp_context=multiprocessing.get_context("spawn"))


def _grade_in_pool(todo: list[UnitSpec], workers: int, grade, finish) -> list[UnitSpec]:
    """Grade ``todo`` in a pool, calling ``finish`` on each result and removing its unit from ``todo``.

    Returns
    -------
    list of UnitSpec
        Empty if the pool survived; else the units it had handed out and not finished when a
        worker died (the pool hands out units in order, at most ``workers + 1`` ahead).
    """
    submitted = list(todo)
    done = 0
    with _pool(workers) as pool:
        futures = {pool.submit(grade, u): u for u in submitted}
        broken = False
        for future in as_completed(futures):
            unit = futures[future]
            try:
                result = future.result()
            except BrokenProcessPool:
                broken = True
                continue
            except Exception as exc:  # noqa: BLE001 - whatever one unit raised, the others are graded
                result = _grader_error(unit, f"grader error: {type(exc).__name__}: {exc}")
            todo.remove(unit)
            done += 1
            finish(result)
    if not broken:
        return []
    return [u for u in submitted[: done + workers + 1] if u in todo]


def _grade_alone(unit: UnitSpec, grade) -> dict:
    """Grade one unit in a pool of its own; if that pool breaks too, the unit is the culprit."""
    with _pool(1) as pool:
        try:
            return pool.submit(grade, unit).result()
        except BrokenProcessPool:
            return _grader_error(unit, "the grading process died while checking this notebook's outputs; it scores 0 and your TA has been told")
        except Exception as exc:  # noqa: BLE001
            return _grader_error(unit, f"grader error: {type(exc).__name__}: {exc}")


def _grader_error(unit: UnitSpec, reason: str) -> dict:
    source = nbformat.read(unit.source, as_version=4)
    return zero_result(unit, source, "grader-error", reason, time.monotonic()) | {"feedback_html": None, "autograded_notebook": None}


def _record(out: Path, autograded: Path, gb, result: dict) -> None:
    record.write_feedback(out, result)
    record.write_autograded(autograded, result)
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
