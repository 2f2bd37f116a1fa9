"""``deformlab grade --scheduler``: a real Dask scheduler and worker processes on 127.0.0.1.

A slice of the corpus (tests/corpus) is graded twice with one seed: by the local
process pool and on a cluster started here the way a TA starts one
(``dask scheduler``, ``dask worker``), one of whose workers is killed in the
middle of the run. Every unit must be graded exactly once, and every score must
equal the pool's.
"""

from __future__ import annotations

import contextlib
import csv
import json
import threading
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import pytest

from tests.corpus import build_submission, load_corpus, student_id
from grader.paths import CoursePaths
from grader.pipeline.distributed import parse_scheduler
from grader.pipeline.run import GradeOptions, grade_class

distributed = pytest.importorskip("distributed", reason='the dask extra is not installed: pip install "deformlab[dask]"')
pytestmark = [pytest.mark.slow, pytest.mark.filterwarnings("ignore::nbformat.warnings.DuplicateCellId")]

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
SEED = 424242
#: A correct submission and bugs that lose points; the ARAP one also has feedback pictures.
ENTRIES = [e for e in load_corpus(ROOT / "tests" / "corpus") if e.name in
           ("noisy_on_stderr", "centroid_ignores_weights", "no_sign_correction", "solve_energy_before_global")]


def _start(args: list[str], log: Path, env: dict) -> subprocess.Popen:
    """``dask ARGS``, which dies with this process however it ends (a time limit's SIGKILL included)."""
    owned = [sys.executable, "-m", "grader.sandbox.lifetime", str(os.getpid())]
    return subprocess.Popen([*owned, str(BIN / "dask"), *args], stdout=open(log, "wb"), stderr=subprocess.STDOUT, env=env)


def _wait_for(predicate, timeout: float, what: str):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def _rows(out: Path) -> list[dict]:
    with open(out / "grades.csv", newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def course(make_course):
    tmp = Path(tempfile.mkdtemp(prefix="dl-dask-"))
    root = make_course(tmp)
    submitted = tmp / "submitted"
    for entry in ENTRIES:
        build_submission(entry, root / "assignments" / "source" / "deformation", submitted, student_id(entry), {})
    env = dict(os.environ, DEFORMLAB_ROOT=str(root), PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    yield tmp, root, submitted, env
    shutil.rmtree(tmp, ignore_errors=True)


@contextlib.contextmanager
def started_cluster(tmp: Path, env: dict, sandboxing: tuple[str, ...]):
    """A scheduler, sandboxing workers named ``sandboxing`` (no nanny: a killed worker stays dead) and one without bubblewrap."""
    tmp.mkdir(parents=True, exist_ok=True)
    scheduler_file = tmp / "scheduler.json"
    procs = [_start(["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file", str(scheduler_file)], tmp / "scheduler.log", env)]
    try:
        _wait_for(scheduler_file.is_file, 60, "the scheduler's address")
        address = json.loads(scheduler_file.read_text())["address"]
        # --death-timeout: a worker that lost its scheduler closes instead of waiting for it forever
        common = ["worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard", "--host", "127.0.0.1", "--death-timeout", "60"]
        workers = {}
        for name in sandboxing:
            workers[name] = _start([*common, "--name", name, "--local-directory", str(tmp / name)], tmp / f"{name}.log", env)
        # A machine without bubblewrap: nothing named bwrap on its PATH.
        workers["nobwrap"] = _start([*common, "--name", "nobwrap", "--local-directory", str(tmp / "nobwrap")], tmp / "nobwrap.log",
                                    dict(env, PATH=str(tmp / "empty-path")))
        procs += workers.values()
        with distributed.Client(address, timeout="30s") as client:
            client.wait_for_workers(len(workers), timeout=120)
            names = {info["name"]: addr for addr, info in client.scheduler_info()["workers"].items()}
        yield address, workers, names
    finally:
        for proc in reversed(procs):  # workers first, so none waits to reconnect to a closed scheduler
            if proc.poll() is None:
                proc.terminate()
        for proc in procs:
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()


@pytest.fixture(scope="module")
def cluster(course):
    """Two sandboxing workers, w1 and w2, and one without bubblewrap."""
    tmp, _, _, env = course
    with started_cluster(tmp, env, ("w1", "w2")) as started:
        yield started


@pytest.fixture(scope="module")
def pool_rows(course):
    tmp, root, submitted, _ = course
    grade_class(submitted, tmp / "out-pool", GradeOptions(workers=2, timeout=30, db_url=f"sqlite:///{tmp}/pool.db", seed=SEED, progress=False), CoursePaths(root))
    return _rows(tmp / "out-pool")


@pytest.fixture(scope="module")
def dask_run(course, cluster):
    """``deformlab grade --scheduler`` with worker w1 killed (SIGKILL) while it grades a submitted notebook."""
    tmp, root, submitted, env = course
    address, workers, names = cluster
    out = tmp / "out-dask"
    grade = subprocess.Popen(
        [str(BIN / "deformlab"), "--course", str(root), "grade", str(submitted), "--out", str(out),
         "--db", f"sqlite:///{tmp}/dask.db", "--seed", str(SEED), "--timeout", "30", "--scheduler", address],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
    )
    executing = {(student_id(e), e.notebook) for e in ENTRIES}
    with distributed.Client(address, timeout="30s") as client:

        def w1_grading_a_submission():
            keys = client.processing(workers=[names["w1"]]).get(names["w1"], [])
            return [k for k in keys if any(k.startswith(f"grade-{sid}-{nb}-") for sid, nb in executing)]

        in_flight = _wait_for(w1_grading_a_submission, 300, "worker w1 to start grading a submitted notebook")
        time.sleep(1.0)  # well inside the unit: its kernel is starting or running
        logged_before_kill = len((out / "log.jsonl").read_text().splitlines()) if (out / "log.jsonl").exists() else 0
        workers["w1"].send_signal(signal.SIGKILL)
        workers["w1"].wait(timeout=30)
    stdout, stderr = grade.communicate(timeout=900)
    return out, grade.returncode, stderr, in_flight, logged_before_kill


def test_scheduler_addresses_are_checked_before_anything_runs():
    assert parse_scheduler("tcp://10.0.0.5:8786") == ("tcp://10.0.0.5:8786", None)
    assert parse_scheduler("local:3") == ("local", 3)
    for bad in ("10.0.0.5:8786", "local:0", "local:two", "tcp://host", "http://host:8786"):
        with pytest.raises(ValueError, match="--scheduler must be"):
            parse_scheduler(bad)


def test_a_killed_worker_loses_no_unit_and_grades_none_twice(dask_run, source_notebooks):
    out, code, stderr, in_flight, logged_before_kill = dask_run
    assert code == 0, stderr[-3000:]
    expected = {(student_id(e), nb) for e in ENTRIES for nb in source_notebooks}
    assert logged_before_kill < len(expected), "the worker was killed after the run had finished"
    assert in_flight
    log = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    counts = Counter((r["student_id"], r["notebook"]) for r in log)
    assert set(counts) == expected and set(counts.values()) == {1}
    assert {r["status"] for r in log} <= {"graded", "missing", "graded-with-incidents"}
    assert {(r["student_id"], r["notebook"]) for r in _rows(out)} == expected


def test_scores_on_the_cluster_equal_the_process_pool_scores(dask_run, pool_rows):
    out, code, stderr, _, _ = dask_run
    assert code == 0, stderr[-3000:]
    assert _rows(out) == pool_rows
    lost = {(r["student_id"], r["notebook"]) for r in pool_rows if float(r["score"]) < float(r["max_score"])}
    assert {sid for sid, _ in lost} >= {"centroid_ignores_weights", "no_sign_correction", "solve_energy_before_global"}


def test_feedback_pictures_show_the_functions_that_failed_only(course, pool_rows):
    # solve_energy_before_global loses arap_solve only: laplacian_editing, pictured too when it fails, passes.
    tmp = course[0]
    page = (tmp / "out-pool" / "feedback" / "solve_energy_before_global" / "03b_arap_global.html").read_text()
    assert "energy after each iteration" in page and "arap_solve" in page and "your deformed mesh (left)" in page
    assert "your edited mesh (left)" not in page  # laplacian_editing's picture: it passed


def test_a_worker_without_bubblewrap_refuses_units_and_the_ta_is_told(dask_run, cluster):
    _, _, stderr, _, _ = dask_run
    _, _, names = cluster
    assert f"without bubblewrap get no units: {names['nobwrap']}" in stderr


def test_a_local_cluster_grades_every_unit(course, tmp_path, source_notebooks):
    _, root, _, env = course
    submitted = tmp_path / "submitted"
    (submitted / "ada" / "deformation").mkdir(parents=True)
    (submitted / "ada" / "deformation" / "01_shape_matching.ipynb").write_text("{not json")
    (submitted / "bob" / "deformation").mkdir(parents=True)  # a student who handed in nothing
    run = subprocess.run(
        [str(BIN / "deformlab"), "--course", str(root), "grade", str(submitted), "--out", str(tmp_path / "out"),
         "--db", f"sqlite:///{tmp_path}/gb.db", "--seed", "1", "--scheduler", "local:2"],
        capture_output=True, text=True, env=env, timeout=600,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    log = {(r["student_id"], r["notebook"]): r["status"] for r in map(json.loads, (tmp_path / "out" / "log.jsonl").read_text().splitlines())}
    assert log == {(s, nb): "invalid" if (s, nb) == ("ada", "01_shape_matching") else "missing" for s in ("ada", "bob") for nb in source_notebooks}


def test_units_pinned_to_sandboxing_workers_that_all_died_are_recorded_not_waited_for(course, tmp_path, monkeypatch, source_notebooks):
    import grader.pipeline.distributed as dask_grading

    _, root, submitted, env = course
    monkeypatch.setattr(dask_grading, "STALL_SECONDS", 5.0)
    monkeypatch.setattr(dask_grading, "WATCH_SECONDS", 1.0)
    with started_cluster(tmp_path / "cluster", env, ("only",)) as (address, workers, names):
        killed = threading.Event()

        def kill_when_busy():
            with distributed.Client(address, timeout="30s") as client:
                _wait_for(lambda: client.processing(workers=[names["only"]]).get(names["only"]), 300, "the worker to start a unit")
            workers["only"].send_signal(signal.SIGKILL)
            killed.set()

        killer = threading.Thread(target=kill_when_busy, daemon=True)
        killer.start()
        started = time.monotonic()
        results = grade_class(submitted, tmp_path / "out", GradeOptions(
            timeout=30, db_url=f"sqlite:///{tmp_path}/gb.db", seed=SEED, progress=False, scheduler=address), CoursePaths(root))
        killer.join(timeout=60)
    assert killed.is_set()
    expected = {(student_id(e), nb) for e in ENTRIES for nb in source_notebooks}
    assert {(r["student_id"], r["notebook"]) for r in _rows(tmp_path / "out")} == expected
    given_up = [r for r in results if r["status"] == "grader-error"]
    assert given_up and all("no Dask worker able to grade was left" in " ".join(r["reasons"]) for r in given_up)
    assert time.monotonic() - started < 600
