"""Cost per notebook of ``deformlab grade`` and where one notebook's wall time goes.

A class of N students (default 5; ``DEFORMLAB_BENCH_SCALE_STUDENTS``) hands in the
whole assignment, solved. It is graded by the process pool (workers = cores) and
by a local Dask cluster (``--scheduler local:<cores>``); each prints
machine-core-seconds per notebook (wall × cores / notebooks, the issue's target:
≤ 0.5) and the CPU seconds the whole process tree used per notebook (so idle
cores show as the gap). Then one student's notebooks are graded one by one in
this process with timers around each step, for the breakdown of a unit's wall
time: kernel start, cells run (definitions and imports, replayed definitions,
collection), kernel shut-down, verification, feedback pictures, and the rest.
"""

from __future__ import annotations

import functools
import os
import resource
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import nbformat

from grader.build.source_notebook import build_sources
from grader.corpus import student_notebook
from grader.paths import CoursePaths, course_paths
from grader.pipeline import unit as unit_module
from grader.pipeline.run import GradeOptions, ensure_gradebook, grade_class


def _cpu_seconds() -> float:
    """CPU time of this process and of every descendant it has reaped (workers, kernels)."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _make_class(root: Path, students: int) -> tuple[CoursePaths, Path]:
    repo = course_paths()
    (root / "course").mkdir()
    for name in ("data", "starter", "notebooks"):
        (root / "course" / name).symlink_to(repo.root / name)
    paths = CoursePaths(root / "course")
    sources = build_sources(repo.notebooks, paths.source, "deformation")
    submitted = root / "submitted"
    for k in range(students):
        folder = submitted / f"student{k:02d}" / "deformation"
        folder.mkdir(parents=True)
        for source in sources:
            nbformat.write(student_notebook(nbformat.read(source, as_version=4), {}), folder / source.name)
    return paths, submitted


def _graded(paths: CoursePaths, submitted: Path, out: Path, options: GradeOptions) -> dict:
    cores = os.cpu_count() or 1
    # nbgrader's generate_assignment fills a new gradebook once per course: timed apart from grading.
    start = time.perf_counter()
    ensure_gradebook(paths, options.db_url, options.assignment)
    setup = time.perf_counter() - start
    cpu, start = _cpu_seconds(), time.perf_counter()
    results = grade_class(submitted, out, options, paths)
    wall, cpu = time.perf_counter() - start, _cpu_seconds() - cpu
    full = sum(r["score"] == r["max_score"] for r in results)
    return {"notebooks": len(results), "full marks": full, "gradebook set-up, once per course (s)": setup, "wall (s)": wall,
            "core-s per notebook": wall * cores / len(results), "CPU-s per notebook (process tree)": cpu / len(results),
            "cores × wall not used by this run (%)": 100 * max(0.0, 1 - cpu / (wall * cores))}


class _Timers:
    """Wall seconds per step, summed over calls; nested steps are subtracted from their parent in ``table``."""

    def __init__(self):
        self.seconds: dict[str, float] = defaultdict(float)

    def wrap(self, owner, name: str, step, classify=None):
        original = getattr(owner, name)

        @functools.wraps(original)
        def timed(*args, **kwargs):
            start = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                self.seconds[classify(*args, **kwargs) if classify else step] += time.perf_counter() - start

        setattr(owner, name, timed)
        return original


def _breakdown(paths: CoursePaths, submitted: Path) -> dict:
    """Grade one student's notebooks here, one after another, with timers around each step."""
    from nbclient import NotebookClient

    from grader.pipeline import execute as execute_module
    from grader.sandbox import SandboxedKernelManager

    timers = _Timers()

    def cell_kind(client, cell, index, **kwargs):
        if cell.source.startswith(execute_module.KERNEL_SIDE_SOURCE[:200]):
            return "execute: collection cells"
        return "execute: replayed definitions" if kwargs.get("store_history") is False else "execute: definition cells (imports)"

    patches = [
        (unit_module, "sanitize", "sanitize", None),
        (unit_module, "write_fixtures", "hidden inputs (reference, fixtures)", None),
        (unit_module, "execute", "execute (total)", None),
        (NotebookClient, "start_new_kernel", "execute: kernel start (sandbox, process)", None),
        (NotebookClient, "start_new_kernel_client", "execute: kernel start (connect, wait until ready)", None),
        (NotebookClient, "execute_cell", None, cell_kind),
        (SandboxedKernelManager, "shutdown_kernel", "execute: kernel shut-down", None),
        (unit_module, "read_outputs", "read outputs", None),
        (unit_module, "verify", "verification", None),
        (unit_module, "feedback_html", "feedback page and pictures", None),
    ]
    # The reference's outputs on the hidden cases are computed once per worker process (cached):
    # timed apart, so the steps below are what every further unit costs.
    from grader.pipeline.verify import graded_cells, hidden_cases

    start = time.perf_counter()
    for source in paths.source_notebooks():
        for cell in graded_cells(nbformat.read(source, as_version=4)):
            hidden_cases(cell.function, 1)
    once = time.perf_counter() - start
    originals = [(owner, name, timers.wrap(owner, name, step, classify)) for owner, name, step, classify in patches]
    try:
        readonly = [str(paths.data), str(paths.starter)]
        folder = next(iter(sorted(submitted.iterdir()))) / "deformation"
        units, wall, cpu = 0, 0.0, 0.0
        for source in paths.source_notebooks():
            content, digest, error = unit_module.read_submission_bytes(folder / source.name)
            spec = unit_module.UnitSpec(student_id=folder.parent.name, notebook=source.stem, submission=content,
                                        source=source.read_text(), seed=1, submission_sha256=digest, submission_error=error)
            c0, t0 = _cpu_seconds(), time.perf_counter()
            unit_module.grade_unit(spec, readonly)
            wall += time.perf_counter() - t0
            cpu += _cpu_seconds() - c0
            units += 1
    finally:
        for owner, name, original in originals:
            setattr(owner, name, original)
    s = timers.seconds
    inside = sum(v for k, v in s.items() if k.startswith("execute: "))
    table = {k: v / units for k, v in sorted(s.items()) if k != "execute (total)"}
    table["execute: the rest (waits between cells, clean-up)"] = (s["execute (total)"] - inside) / units
    table["rest of the unit"] = (wall - sum(v for k, v in s.items() if not k.startswith("execute: "))) / units
    return {"reference outputs of every hidden case, once per worker process (s)": once, "unit wall (s)": wall / units, "unit CPU-s (process tree)": cpu / units,
            **{f"  {k} (s)": v for k, v in table.items()}}


def main(students: int | None = None) -> dict:
    students = students or int(os.environ.get("DEFORMLAB_BENCH_SCALE_STUDENTS", "5"))
    cores = os.cpu_count() or 1
    figures: dict = {"students": students, "cores": cores, "load average before": os.getloadavg()[0]}
    with tempfile.TemporaryDirectory(prefix="dl-bench-scale-") as tmp:
        root = Path(tmp)
        paths, submitted = _make_class(root, students)
        common = dict(seed=1, progress=False)
        for engine, options in (
            ("pool", GradeOptions(workers=cores, db_url=f"sqlite:///{root}/pool.db", autograded=root / "a-pool", **common)),
            ("dask", GradeOptions(scheduler=f"local:{cores}", db_url=f"sqlite:///{root}/dask.db", autograded=root / "a-dask", **common)),
        ):
            for key, value in _graded(paths, submitted, root / f"out-{engine}", options).items():
                figures[f"{engine}: {key}"] = value
        figures["pool: notebooks per second"] = figures["pool: notebooks"] / figures["pool: wall (s)"]
        figures["dask: notebooks per second"] = figures["dask: notebooks"] / figures["dask: wall (s)"]
        figures.update({f"one unit, sequential: {k}": v for k, v in _breakdown(paths, submitted).items()})
    for k, v in figures.items():
        print(f"{k:<80} {v:.3g}" if isinstance(v, float) else f"{k:<80} {v}")
    return figures


if __name__ == "__main__":
    main()
