"""``deformlab grade``: a class of submissions through the pipeline, in parallel.

sanitize → execute in a sandbox → collect → verify run inside each work unit
(``grader.pipeline.unit``); this module finds the units, runs them in a process
pool, and records each result as it arrives (``grader.pipeline.record``).
"""

from __future__ import annotations

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
from grader.pipeline.submitted import student_folders
from grader.pipeline.unit import UnitSpec, grade_unit, sha256_of, zero_result
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES


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
    student: str | None = None  # grade only this student again; the others' results are read from OUT as they are


def _worker_init() -> None:
    # Each worker is one of N parallel graders: one BLAS thread each keeps N cores busy, not N².
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"


def find_submission(folder: Path, notebook: str) -> tuple[Path | None, list[str]]:
    """The student's file for ``notebook``, also when renamed (matched by the notebook's own metadata)."""
    exact = folder / f"{notebook}.ipynb"
    if exact.is_file():
        return exact, []
    if folder.is_dir():
        for candidate in sorted(folder.glob("*.ipynb")):
            try:
                meta = json.loads(candidate.read_text(encoding="utf-8")).get("metadata", {})
            except (OSError, ValueError, AttributeError):
                continue
            if isinstance(meta, dict) and (meta.get("deformlab") or {}).get("notebook") == notebook:
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
    """One ``UnitSpec`` per student × notebook: students from the folder and from the gradebook's roster."""
    folders = student_folders(submitted, options.assignment)
    units = []
    for sid in sorted(set(folders) | set(roster)):
        folder = folders.get(sid)
        for source in sources:
            notebook = source.stem
            notes: list[str] = []
            if folder is None:
                path = None
                notes.append("no submission folder for this student")
            else:
                path, notes = find_submission(folder / options.assignment, notebook)
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
                )
            )
    return units


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


def grade_class(submitted: Path, out: Path, options: GradeOptions, paths: CoursePaths | None = None) -> list[dict]:
    """Grade every student × notebook under ``submitted``; write ``out``.

    ``paths`` selects the course (its source notebooks, data/ and starter/);
    default: this checkout.

    Returns
    -------
    list of dict
        One result per student × notebook (see ``grade_unit``).

    Raises
    ------
    FileNotFoundError
        If ``submitted`` is not a folder.
    """
    submitted, out = Path(submitted), Path(out)
    if not submitted.is_dir():
        raise FileNotFoundError(f"SUBMITTED must be a folder of student folders: {submitted} is not a folder")
    out.mkdir(parents=True, exist_ok=True)
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
        while todo:
            broken = False
            # spawn, not fork: a forked child inherits jupyter's event-loop thread as a dead handle and hangs.
            with ProcessPoolExecutor(max_workers=workers, initializer=_worker_init, mp_context=multiprocessing.get_context("spawn")) as pool:
                futures = {pool.submit(grade_unit, u): u for u in todo}
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
                    _record(out, autograded, gb, result)
                    results.append(result)
                    bar.update(1)
            if broken and todo:
                # A worker died (not a kernel: those are handled inside the unit). Retry the rest once more
                # one at a time; the unit that killed the pool is recorded as a grader error.
                culprit = todo.pop(0)
                result = _grader_error(culprit, "a grading worker process died while grading this notebook")
                _record(out, autograded, gb, result)
                results.append(result)
                bar.update(1)
                workers = 1
    bar.close()
    record.write_grades_csv(out, results)
    record.compact_log(out)
    _print_summary(results, out)
    return results


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
