"""``deformlab grade``: a class of submissions through the pipeline, in parallel.

sanitize → execute in a sandbox → collect → verify run inside each work unit
(``grader.pipeline.unit``); this module finds the units, runs them in a process
pool or on a Dask cluster (``grader.pipeline.distributed``), and records each
result as it arrives, in this one process (``grader.pipeline.record``).
"""

from __future__ import annotations

import dataclasses

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

from grader.course_pack import default_assignment, pack
from grader.paths import CoursePaths, course_paths
from grader.pipeline import record
from grader.pipeline.sanitize import read_submission_bytes
from grader.pipeline.submitted import check_submitted, student_folders
from grader.pipeline.unit import UnitSpec, grade_unit, load_submission, zero_result
from grader.pipeline.workers import init_worker
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
    assignment: str | None = None  # None: the course's default assignment (c.DeformLab.default_assignment)
    progress: bool = True
    autograded: Path | None = None  # where executed notebooks go for formgrader; default: the course's autograded/
    wall: float = 900.0  # seconds per notebook
    disk_bytes: int = DEFAULT_FILE_BYTES  # each student's workdir
    student: str | None = None  # grade only this student again; the others' results are read from OUT as they are
    scheduler: str | None = None  # a Dask cluster: "tcp://HOST:PORT" or "local:N"; None: a local process pool
    allow_unsandboxed: bool = False  # Dask workers without bubblewrap grade anyway (they refuse units otherwise)


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
    """One unit per student × notebook: students from the folder and from the gradebook's roster.

    A student folder that is a link is not followed (its student gets a row saying so).
    """
    assignment = options.assignment or default_assignment()
    folders = student_folders(submitted, assignment)
    units = []
    for sid in sorted(set(folders) | set(roster)):
        folder = folders.get(sid)
        for source in sources:
            notebook = source.stem
            path = None
            if folder is None:
                notes = ["no submission folder for this student"]
            elif folder.is_symlink():
                notes = ["the submission folder is a link, which is not followed"]
            else:
                try:
                    path, notes = find_submission(folder / assignment, notebook)
                except OSError as exc:  # an unreadable folder costs its own student only
                    notes = [f"cannot read the submission folder: {exc.strerror}"]
            units.append(PlannedUnit(sid, notebook, path, source, tuple(notes), folder is not None))
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


def unit_spec(unit: PlannedUnit, seed: int, options: GradeOptions, source_text: str) -> UnitSpec:
    """The self-contained work unit: the submitted bytes are read here, on the recording host."""
    content, digest, error = load_submission(unit.submission)
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
        wall=options.wall,
        disk_bytes=options.disk_bytes,
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

    if options.assignment is None:
        options = dataclasses.replace(options, assignment=default_assignment())
    # planned before anything is built or written: a wrong folder or assignment is refused at once
    pack(options.assignment)
    check_submitted(submitted, options.assignment)
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


def _pool(workers: int) -> ProcessPoolExecutor:
    # spawn, not fork: a forked child inherits jupyter's event-loop thread as a dead handle and hangs.
    return ProcessPoolExecutor(max_workers=workers, initializer=init_worker, initargs=(os.getpid(),), mp_context=multiprocessing.get_context("spawn"))


def grade_in_pool(
    todo: list[PlannedUnit],
    spec_of: Callable[[PlannedUnit], UnitSpec],
    error_of: Callable[[PlannedUnit, str], dict],
    workers: int,
    readonly: list[str],
    grade: Callable = grade_unit,
) -> Iterator[tuple[PlannedUnit, dict]]:
    """Grade ``todo`` in a local process pool; yield ``(unit, result)`` in order of completion.

    At most two units per worker are in flight, so the submitted bytes of a
    large class are never all in memory. If a grading worker dies (not a
    kernel: those are handled inside the unit), only a unit the pool held can
    have killed it: each of those is graded again alone, in a pool of its own,
    so that a culprit breaks only its own pool and its neighbours keep their grades.
    """
    remaining = dict(enumerate(todo))
    while remaining:
        queue = list(remaining)
        suspects: list[int] = []
        with _pool(workers) as pool:
            pending: dict = {}
            while queue or pending:
                while queue and len(pending) < 2 * workers and not suspects:
                    try:
                        pending[pool.submit(grade, spec_of(remaining[queue[0]]), readonly)] = queue[0]
                    except BrokenProcessPool:
                        # a worker died since the last wait: what is pending fails below,
                        # and the rest of the queue goes to the next pool
                        queue.clear()
                        break
                    queue.pop(0)
                if not pending:
                    break
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    i = pending.pop(future)
                    try:
                        result = future.result()
                    except BrokenProcessPool:
                        suspects.append(i)
                        continue
                    except Exception as exc:  # noqa: BLE001 - whatever one unit raised, the others are graded
                        result = error_of(remaining[i], f"grader error: {type(exc).__name__}: {exc}")
                    yield remaining.pop(i), result
        for i in suspects:
            unit = remaining.pop(i)
            yield unit, _grade_alone(unit, spec_of, error_of, readonly, grade)
        if suspects:
            remove_stale_workspaces()  # what the dead worker held (its locks name it: swept at once)
            remove_stale_limits()


def _grade_alone(unit: PlannedUnit, spec_of, error_of, readonly: list[str], grade) -> dict:
    """Grade one unit in a pool of its own; if that pool breaks too, the unit is the culprit."""
    with _pool(1) as pool:
        try:
            return pool.submit(grade, spec_of(unit), readonly).result()
        except BrokenProcessPool:
            return error_of(unit, "the grading process died while checking this notebook's outputs; it scores 0 and your TA has been told")
        except Exception as exc:  # noqa: BLE001
            return error_of(unit, f"grader error: {type(exc).__name__}: {exc}")


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
