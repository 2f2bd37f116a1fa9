"""``deformlab grade``: a class of submissions through the pipeline, in parallel.

sanitize → execute in a sandbox → collect → verify run inside each work unit
(``grader.pipeline.unit``); this module finds the units, runs them in a process
pool or on a Dask cluster (``grader.pipeline.distributed``), and records each
result as it arrives, in this one process (``grader.pipeline.record``).
"""

from __future__ import annotations

import fcntl
import json
import multiprocessing
import os
import secrets
import sys
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path

import nbformat

from grader.contract import ASSIGNMENT
from grader.paths import CoursePaths, course_paths
from grader.pipeline import record
from grader.pipeline.unit import UnitSpec, grade_unit, read_submission_bytes, zero_result
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
    scheduler: str | None = None  # a Dask cluster: "tcp://HOST:PORT" or "local:N"; None: a local process pool
    allow_unsandboxed: bool = False  # Dask workers without bubblewrap grade anyway (they refuse units otherwise)


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
        from grader.build.release import ReleaseError, generate_assignment

        try:
            generate_assignment(paths, assignment, db_url)
        except ReleaseError:
            if not known():
                raise


def _known_students(db_url: str) -> list[str]:
    with record.open_gradebook(db_url) as gb:
        return [s.id for s in gb.students]


@dataclass(frozen=True)
class PlannedUnit:
    """One student × notebook as found on this host (``unit_spec`` makes the self-contained ``UnitSpec``)."""

    student_id: str
    notebook: str
    submission: Path | None
    source: Path
    notes: tuple[str, ...] = ()
    #: False for a student of the gradebook's roster who has no folder in this run: such a row
    #: is written to grades.csv but never over what another run recorded in the gradebook.
    in_folder: bool = True


def plan_units(submitted: Path, sources: list[Path], options: GradeOptions, roster: list[str]) -> list[PlannedUnit]:
    """One unit per student × notebook: students from the folder and from the gradebook's roster."""
    folders = {p.name: p for p in sorted(Path(submitted).iterdir()) if p.is_dir() and not p.name.startswith(".")}
    units = []
    for sid in sorted(set(folders) | set(roster)):
        folder = folders.get(sid)
        for source in sources:
            notebook = source.stem
            if folder is None:
                path, notes = None, ["no submission folder for this student"]
            else:
                path, notes = find_submission(folder / options.assignment, notebook)
            units.append(PlannedUnit(sid, notebook, path, source, tuple(notes), folder is not None))
    return units


def unit_spec(unit: PlannedUnit, seed: int, options: GradeOptions, source_text: str) -> UnitSpec:
    """The self-contained work unit: the submitted bytes are read here, on the recording host."""
    content, digest, error = read_submission_bytes(unit.submission)
    return UnitSpec(
        student_id=unit.student_id,
        notebook=unit.notebook,
        submission=content,
        source=source_text,
        seed=seed,
        assignment=options.assignment,
        timeout=options.timeout,
        memory_bytes=int(options.memory_gb * 2**30),
        max_processes=options.max_processes,
        notes=list(unit.notes),
        submission_sha256=digest,
        submission_error=error,
    )


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
        and previous.get("submission_sha256") == read_submission_bytes(unit.submission)[1]
        and previous.get("status") != "grader-error"
    ):
        return previous | {"reused": True}
    return None


def grade_class(submitted: Path, out: Path, options: GradeOptions, paths: CoursePaths | None = None) -> list[dict]:
    """Grade every student × notebook under ``submitted``; write ``out``.

    ``paths`` selects the course (its source notebooks, data/ and starter/);
    default: the configured course (``grader.paths.course_paths``). Units run
    in a local process pool, or on a Dask cluster when ``options.scheduler``
    is set; either way this process records each result as it arrives.

    Returns
    -------
    list of dict
        One result per student × notebook (see ``grade_unit``).

    Raises
    ------
    FileNotFoundError
        If ``submitted`` is not a folder.
    ValueError
        If ``options.scheduler`` is malformed or names no reachable cluster.
    """
    submitted, out = Path(submitted), Path(out)
    if not submitted.is_dir():
        raise FileNotFoundError(f"SUBMITTED must be a folder of student folders: {submitted} is not a folder")
    if options.scheduler:
        from grader.pipeline.distributed import parse_scheduler

        parse_scheduler(options.scheduler)  # a typo fails before anything is written
    out.mkdir(parents=True, exist_ok=True)
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
    for unit in units:
        previous = _reusable(out, unit, seed)
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
        stream = grade_in_pool(todo, spec_of, error_of, max(1, options.workers or os.cpu_count() or 1), readonly)

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
    _print_summary(results, out)
    return results


def grade_in_pool(
    todo: list[PlannedUnit],
    spec_of: Callable[[PlannedUnit], UnitSpec],
    error_of: Callable[[PlannedUnit, str], dict],
    workers: int,
    readonly: list[str],
) -> Iterator[tuple[PlannedUnit, dict]]:
    """Grade ``todo`` in a local process pool; yield ``(unit, result)`` in order of completion.

    At most two units per worker are in flight, so the submitted bytes of a
    large class are never all in memory.
    """
    remaining = dict(enumerate(todo))
    while remaining:
        broken = False
        queue = list(remaining)
        # spawn, not fork: a forked child inherits jupyter's event-loop thread as a dead handle and hangs.
        with ProcessPoolExecutor(max_workers=workers, initializer=_worker_init, mp_context=multiprocessing.get_context("spawn")) as pool:
            pending: dict = {}
            while queue or pending:
                while queue and len(pending) < 2 * workers and not broken:
                    i = queue.pop(0)
                    pending[pool.submit(grade_unit, spec_of(remaining[i]), readonly)] = i
                if not pending:
                    break
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    i = pending.pop(future)
                    try:
                        result = future.result()
                    except BrokenProcessPool:
                        broken = True
                        continue
                    except Exception as exc:  # noqa: BLE001 - whatever one unit raised, the others are graded
                        result = error_of(remaining[i], f"grader error: {type(exc).__name__}: {exc}")
                    yield remaining.pop(i), result
        if broken and remaining:
            # A worker died (not a kernel: those are handled inside the unit). Retry the rest once more
            # one at a time; the unit that killed the pool is recorded as a grader error.
            culprit = remaining.pop(next(iter(remaining)))
            yield culprit, error_of(culprit, "a grading worker process died while grading this notebook")
            workers = 1


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
