"""Cost per notebook of ``deformlab grade`` and where one notebook's wall time goes.

A class of N students (default 12; ``DEFORMLAB_BENCH_SCALE_STUDENTS``) hands in the
whole assignment, solved. Twelve, so that the steady state below starts after each
worker has met every notebook once (its first unit of a notebook computes the
reference's outputs on that notebook's hidden cases: 2 s of CPU per worker in all).
It is graded by the process pool (workers = cores) and by a local Dask cluster
(``--scheduler local:<cores>``); each prints machine-core-seconds per notebook (wall
× cores / notebooks, the issue's target: ≤ 0.5), the CPU seconds everything this
benchmark started used per notebook (grader, workers and the sandboxed kernels), and
how much of cores × wall that leaves unused (idle, or used by other programs on a
shared machine; the machine's own idle share over the run is printed beside it), and
the steady state's core-seconds per notebook, between the first and last quarter's
results, which is what a large class pays once the run's fixed costs are spread
thin. Then one student's notebooks are graded one by one in this process with timers
around each step, for the breakdown of a unit's wall time (each next unit's sandbox
pre-started, as in a worker): kernel start, waits, cells run (definitions and
imports, replayed definitions, collection), peak-memory readings, garbage
collection, kernel shut-down, verification, feedback pictures, and the rest.

CPU is read from a ``cpuacct`` cgroup of this benchmark's own where the machine
lets it create one (root on cgroup v1, or a delegated cgroup v2): it counts the
kernels, which the grader kills and so never reaps with their CPU times.
Elsewhere ``getrusage`` of this process and its reaped children stands in, and
the figure's name says it misses the kernels.
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
from tests.corpus import student_notebook
from grader.paths import CoursePaths, course_paths
from grader.pipeline import run as run_module
from grader.pipeline import unit as unit_module
from grader.pipeline.run import GradeOptions, ensure_gradebook, grade_class
from grader.sandbox import fork_server, spares
from grader.sandbox.bwrap import SandboxSpec, sandbox_env
from tests.course_copy import copy_course_config


class _CpuMeter:
    """CPU seconds of this process and everything it starts, from a cgroup of its own where possible.

    ``whole`` says whether the kernels are counted (a cgroup) or not (``getrusage``: the
    grader SIGKILLs each sandbox, so the kernels' CPU never reaches a reaped parent).
    """

    def __init__(self):
        self.group: Path | None = None
        self.parent: Path | None = None
        for usage in ("cpuacct.usage", "cpu.stat"):
            self.group = self._own_group(usage)
            if self.group is not None:
                self.usage = usage
                break

    def _own_group(self, usage: str) -> Path | None:
        try:
            lines = Path("/proc/self/cgroup").read_text().splitlines()
        except OSError:
            return None
        for line in lines:
            _, controllers, path = line.split(":", 2)
            if usage == "cpuacct.usage" and "cpuacct" in controllers.split(","):
                parent = Path("/sys/fs/cgroup/cpuacct") / path.lstrip("/")
            elif usage == "cpu.stat" and controllers == "":
                parent = Path("/sys/fs/cgroup") / path.lstrip("/")
            else:
                continue
            group = parent / f"deformlab-bench-{os.getpid()}"
            try:
                group.mkdir()
                (group / "cgroup.procs").write_text(str(os.getpid()))
            except OSError:
                try:
                    group.rmdir()
                except OSError:
                    pass
                continue
            self.parent = parent
            return group
        return None

    @property
    def whole(self) -> bool:
        return self.group is not None

    def seconds(self) -> float:
        if self.group is None:
            own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
            return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime
        text = (self.group / self.usage).read_text()
        if self.usage == "cpuacct.usage":
            return int(text) / 1e9
        return int(text.split("usage_usec")[1].split()[0]) / 1e6

    def close(self) -> None:
        if self.group is None:
            return
        (self.parent / "cgroup.procs").write_text(str(os.getpid()))
        deadline = time.monotonic() + 30
        while True:  # processes this benchmark started (Dask's, multiprocessing's helpers) may still be exiting
            try:
                self.group.rmdir()
                return
            except OSError:
                if time.monotonic() > deadline:
                    print(f"note: {self.group} still holds processes; remove it once they exit")
                    return
                time.sleep(0.5)


def _machine_idle() -> tuple[float, float]:
    """``(idle, total)`` jiffies of the whole machine, from /proc/stat."""
    fields = [int(x) for x in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
    return fields[3] + fields[4], sum(fields[:8])


def _cpu_name(meter: _CpuMeter) -> str:
    return "CPU-s per notebook (grader, workers, kernels)" if meter.whole else "CPU-s per notebook (grader and workers; kernels not counted)"


def _make_class(root: Path, students: int) -> tuple[CoursePaths, Path]:
    repo = course_paths()
    (root / "course").mkdir()
    for name in ("data", "starter", "notebooks"):
        (root / "course" / name).symlink_to(repo.root / name)
    paths = CoursePaths(root / "course")
    copy_course_config(paths.course)  # the course packs: grading workers read them from this course
    sources = build_sources(paths.source, "deformation")
    submitted = root / "submitted"
    for k in range(students):
        folder = submitted / f"student{k:02d}" / "deformation"
        folder.mkdir(parents=True)
        for source in sources:
            nbformat.write(student_notebook(nbformat.read(source, as_version=4), {}), folder / source.name)
    return paths, submitted


def _graded(paths: CoursePaths, submitted: Path, out: Path, options: GradeOptions, meter: _CpuMeter) -> dict:
    cores = os.cpu_count() or 1
    # nbgrader's generate_assignment fills a new gradebook once per course: timed apart from grading.
    start = time.perf_counter()
    ensure_gradebook(paths, options.db_url, options.assignment)
    setup = time.perf_counter() - start
    load = os.getloadavg()[0]
    idle, total = _machine_idle()
    arrivals = []
    record_result = run_module.record_result

    def timed_record(*args, **kwargs):
        arrivals.append(time.perf_counter())
        return record_result(*args, **kwargs)

    run_module.record_result = timed_record
    try:
        cpu, start = meter.seconds(), time.perf_counter()
        results = grade_class(submitted, out, options, paths)
        wall, cpu = time.perf_counter() - start, meter.seconds() - cpu
    finally:
        run_module.record_result = record_result
    idle2, total2 = _machine_idle()
    full = sum(r["score"] == r["max_score"] for r in results)
    return {"notebooks": len(results), "full marks": full, "gradebook set-up, once per course (s)": setup, "wall (s)": wall,
            "core-s per notebook": wall * cores / len(results), _cpu_name(meter): cpu / len(results),
            "cores × wall not used by this run (%)": 100 * max(0.0, 1 - cpu / (wall * cores)),
            "machine idle over the run, all programs (%)": 100 * (idle2 - idle) / max(1, total2 - total),
            "load average (1 min) at start": load,
            "core-s per notebook, steady state (middle half of the results)": _steady_core_seconds(arrivals, cores)}


def _steady_core_seconds(arrivals: list[float], cores: int) -> float:
    """Cores × wall per notebook between the arrivals of the first and last quarter's results.

    What a class of 10,000 pays per notebook: the run's fixed costs (workers
    starting, each computing the reference's outputs once, the last units
    finishing on fewer workers than the pool has) fall outside that window.
    """
    first, last = len(arrivals) // 4, (3 * len(arrivals)) // 4
    if last - first < 2:
        return float("nan")
    return (arrivals[last] - arrivals[first]) * cores / (last - first)


class _Timers:
    """Wall seconds per step, summed over calls; nested steps are subtracted from their parent in ``table``."""

    def __init__(self):
        self.seconds: dict[str, float] = defaultdict(float)

    def wrap(self, owner, name: str, step, classify=None):
        original = getattr(owner, name)
        if name == "gc":  # the module: time its collect(), pass the rest through
            timed_collect = self._timed(original.collect, step, None)

            class _TimedGc:
                collect = staticmethod(timed_collect)

                def __getattr__(self, attribute):
                    return getattr(original, attribute)

            setattr(owner, name, _TimedGc())
            return original
        setattr(owner, name, self._timed(original, step, classify))
        return original

    def _timed(self, original, step, classify):

        @functools.wraps(original)
        def timed(*args, **kwargs):
            start = time.perf_counter()
            try:
                return original(*args, **kwargs)
            finally:
                self.seconds[classify(*args, **kwargs) if classify else step] += time.perf_counter() - start

        return timed


def _breakdown(paths: CoursePaths, submitted: Path, meter: _CpuMeter) -> dict:
    """Grade one student's notebooks here, one after another, with timers around each step."""
    from nbclient import NotebookClient

    from grader.pipeline import execute as execute_module
    from grader.sandbox import SandboxedKernelManager

    timers = _Timers()

    def cell_kind(client, cell, index, **kwargs):
        if "__deformlab_collect__(" in cell.source:
            return "execute: collection cells"
        return "execute: replayed definitions" if kwargs.get("store_history") is False else "execute: definition cells (imports)"

    patches = [
        (unit_module, "sanitize", "sanitize", None),
        (unit_module, "write_fixtures", "hidden inputs (reference, fixtures)", None),
        (unit_module, "execute", "execute (total)", None),
        (NotebookClient, "start_new_kernel", "execute: kernel start (sandbox, process, its sockets)", None),
        (NotebookClient, "start_new_kernel_client", "execute: kernel start (connect, wait until ready)", None),
        (execute_module, "peak_memory_bytes", "execute: peak-memory readings", None),
        (execute_module, "gc", "execute: garbage collection", None),
        (NotebookClient, "execute_cell", None, cell_kind),
        (SandboxedKernelManager, "finish_start", "execute: kernel start (sandbox, process, its sockets)", None),
        (SandboxedKernelManager, "shutdown_kernel", "execute: kernel shut-down", None),
        (unit_module, "_prestart_next", "launch of the next unit's sandbox (it boots meanwhile)", None),
        (unit_module, "read_outputs", "read outputs", None),
        (unit_module, "verify", "verification", None),
        (unit_module, "feedback_html", "feedback page and pictures", None),
    ]
    # The reference's outputs on the hidden cases are computed once per worker process (cached):
    # timed apart, so the steps below are what every further unit costs.
    from grader.pipeline.verify import graded_cells, hidden_cases

    start = time.perf_counter()
    for source in paths.source_notebooks("deformation"):
        for cell in graded_cells(nbformat.read(source, as_version=4)):
            hidden_cases(cell.function, 1)
    once = time.perf_counter() - start
    start = time.perf_counter()
    if fork_server.enabled():
        fork_server.start_template(sandbox_env(SandboxSpec(workdir=submitted)))
    template = time.perf_counter() - start
    originals = [(owner, name, timers.wrap(owner, name, step, classify)) for owner, name, step, classify in patches]
    spares.open_pool()  # as grading workers do
    try:
        readonly = [str(paths.data), str(paths.starter)]
        folder = next(iter(sorted(submitted.iterdir()))) / "deformation"
        units, wall, cpu, own = 0, 0.0, 0.0, 0.0
        for source in paths.source_notebooks("deformation"):
            content, digest, error = unit_module.load_submission(folder / source.name)
            spec = unit_module.UnitSpec(student_id=folder.parent.name, notebook=source.stem, submission=content,
                                        source=source.read_text(), seed=1, submission_sha256=digest, submission_error=error)
            c0, p0, t0 = meter.seconds(), time.process_time(), time.perf_counter()
            unit_module.grade_unit(spec, readonly)
            wall += time.perf_counter() - t0
            cpu += meter.seconds() - c0
            own += time.process_time() - p0
            units += 1
    finally:
        for owner, name, original in originals:
            setattr(owner, name, original)
        spares.close_pool()  # the last spare's shut-down is no unit's
        fork_server.stop_template()
    s = timers.seconds
    inside = sum(v for k, v in s.items() if k.startswith("execute: "))
    table = {k: v / units for k, v in sorted(s.items()) if k != "execute (total)"}
    table["execute: the rest (waits between cells, clean-up)"] = (s["execute (total)"] - inside) / units
    table["rest of the unit"] = (wall - sum(v for k, v in s.items() if not k.startswith("execute: "))) / units
    figures = {"reference outputs of every hidden case, once per worker process (s)": once,
               "kernel template's imports, once per worker process (s)": template, "unit wall (s)": wall / units}
    if meter.whole:
        figures |= {"unit CPU-s (grader and kernel)": cpu / units, "unit CPU-s, grader only": own / units,
                    "unit CPU-s, sandbox (kernel, bwrap)": (cpu - own) / units, "unit wall not spent on CPU (s)": (wall - cpu) / units}
    else:
        figures |= {"unit CPU-s, grader only (kernels not counted here)": own / units}
    return figures | {f"  {k} (s)": v for k, v in table.items()}


def main(students: int | None = None) -> dict:
    students = students or int(os.environ.get("DEFORMLAB_BENCH_SCALE_STUDENTS", "12"))
    cores = os.cpu_count() or 1
    figures: dict = {"students": students, "cores": cores, "load average before": os.getloadavg()[0]}
    meter = _CpuMeter()
    try:
        with tempfile.TemporaryDirectory(prefix="dl-bench-scale-") as tmp:
            root = Path(tmp)
            paths, submitted = _make_class(root, students)
            common = dict(seed=1, progress=False, assignment="deformation")
            for engine, options in (
                ("pool", GradeOptions(workers=cores, db_url=f"sqlite:///{root}/pool.db", autograded=root / "a-pool", **common)),
                ("dask", GradeOptions(scheduler=f"local:{cores}", db_url=f"sqlite:///{root}/dask.db", autograded=root / "a-dask", **common)),
            ):
                for key, value in _graded(paths, submitted, root / f"out-{engine}", options, meter).items():
                    figures[f"{engine}: {key}"] = value
            figures["pool: notebooks per second"] = figures["pool: notebooks"] / figures["pool: wall (s)"]
            figures["dask: notebooks per second"] = figures["dask: notebooks"] / figures["dask: wall (s)"]
            figures.update({f"one unit, sequential: {k}": v for k, v in _breakdown(paths, submitted, meter).items()})
    finally:
        meter.close()
    for k, v in figures.items():
        print(f"{k:<80} {v:.3g}" if isinstance(v, float) else f"{k:<80} {v}")
    return figures


if __name__ == "__main__":
    main()
