"""Nothing outlives the process that started it, SIGKILL included.

A real ``deformlab grade`` over a small class is killed (SIGKILL) in the middle
of its run, in the local process pool and on a local Dask cluster: its pool
workers or Dask workers and their grading processes, kernel templates, the
sandboxes of the unit being graded and of the pre-started next one must all
die with it, and the next run's sweep removes the workspaces it left. The Dask
scheduler and workers the suite itself starts must die with the test process
that started them. Processes are found with psutil over the whole host: those
of the run (recorded just before the kill), their descendants, and any whose
command line names the run's private folder. Every wait is a generous poll.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import psutil
import pytest

from tests.corpus import build_submission, load_corpus, student_id
from grader.sandbox.bwrap import bwrap_available
from grader.sandbox.workspace import PREFIX, remove_stale_workspaces

pytestmark = [pytest.mark.slow, pytest.mark.skipif(not bwrap_available(), reason="bubblewrap is missing or cannot create namespaces here")]

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
ENTRIES = [e for e in load_corpus(ROOT / "tests" / "corpus") if e.name in ("centroid_ignores_weights", "no_sign_correction", "solve_energy_before_global")]
#: Seconds everything may take to die or to start: a busy machine is slow, never a failure.
PATIENCE = 180.0


def _wait_for(predicate, timeout: float, what: str):
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value or time.monotonic() > deadline:
            break
        time.sleep(0.2)
    assert value, f"timed out after {timeout} s waiting for {what}"
    return value


def _tree(pid: int) -> dict[tuple[int, float], list[str]]:
    """``(pid, start time) -> command line`` of a process and its descendants."""
    found = {}
    try:
        root = psutil.Process(pid)
        for proc in [root, *root.children(recursive=True)]:
            try:
                found[(proc.pid, proc.create_time())] = proc.cmdline()
            except psutil.Error:
                pass
    except psutil.Error:
        pass
    return found


def _left(marks: set[tuple[int, float]], folder: Path) -> list[str]:
    """Live processes among ``marks``, descended from one of them, or naming ``folder`` on their command line."""
    left = []
    for proc in psutil.process_iter(["pid", "create_time", "cmdline", "status"]):
        try:
            if proc.info["status"] == psutil.STATUS_ZOMBIE:
                continue
            cmdline = " ".join(proc.info["cmdline"] or [])
            lineage = [proc, *proc.parents()]
            if any((p.pid, p.create_time()) in marks for p in lineage) or str(folder) in cmdline:
                left.append(f"{proc.pid}: {cmdline[:300]}")
        except psutil.Error:
            pass
    return left


@pytest.fixture(scope="module")
def course(make_course):
    tmp = Path(tempfile.mkdtemp(prefix="dl-life-"))
    root = make_course(tmp)
    submitted = tmp / "submitted"
    for entry in ENTRIES:
        build_submission(entry, root / "assignments" / "source" / "deformation", submitted, student_id(entry), {})
    yield tmp, root, submitted
    for temp in tmp.glob("run-*/t"):  # a failed test's workspaces, whose tmpfs rmtree cannot remove
        remove_stale_workspaces(temp)
    shutil.rmtree(tmp, ignore_errors=True)


@pytest.mark.parametrize("where", [["--workers", "1"], ["--scheduler", "local:1"]], ids=["process-pool", "dask-local-cluster"])
def test_a_grading_run_killed_mid_run_leaves_no_process_and_the_next_run_sweeps_its_workspaces(course, where):
    tmp, root, submitted = course
    run = Path(tempfile.mkdtemp(prefix="run-", dir=tmp))
    temp = run / "t"  # the run's temporary folder: its workspaces, and no other run's
    temp.mkdir()
    env = dict(os.environ, DEFORMLAB_ROOT=str(root), TMPDIR=str(temp), PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    grade = subprocess.Popen(
        [str(BIN / "deformlab"), "--course", str(root), "grade", str(submitted), "--out", str(run / "out"),
         "--db", f"sqlite:///{run}/gb.db", "--seed", "3", "--timeout", "120", *where],
        stdout=subprocess.DEVNULL, stderr=open(run / "stderr", "wb"), env=env,
    )
    try:
        def busy():
            # a unit's kernel sandbox (bwrap) and the kernel template, after a first notebook was
            # graded: the next unit's sandbox is pre-started while the unit before is verified
            tree = _tree(grade.pid)
            lines = [" ".join(c) for c in tree.values()]
            graded = (run / "out" / "log.jsonl").exists() and '"graded' in (run / "out" / "log.jsonl").read_text()
            ready = graded and any("bwrap" in c for c in lines) and any("kernel_template.py" in c for c in lines)
            return tree if ready else None

        _wait_for(lambda: busy() or grade.poll() is not None, 600, "the run to grade a notebook with a kernel and a template running")
        assert grade.poll() is None, (run / "stderr").read_text()[-3000:]
        tree = busy()
        assert any(PREFIX in " ".join(c) for c in tree.values())  # a sandbox bound to a workspace of the run
        marks = set(tree)
        grade.send_signal(signal.SIGKILL)
        grade.wait()
        _wait_for(lambda: not _left(marks, run), PATIENCE, "every process of the killed run to die")
    finally:
        if grade.poll() is None:
            grade.kill()
            grade.wait()
    left_behind = sorted(temp.glob(f"{PREFIX}*"))
    assert left_behind  # the killed run could not remove the workspaces it was using
    remove_stale_workspaces(temp)  # what the next run does first
    # (Dask's own scratch space, which a local cluster keeps there, is purged by the next Dask worker's start.)
    assert sorted(temp.glob(f"{PREFIX}*")) == []


OWNER = """
import sys, time
from pathlib import Path
from tests.grader.test_grade_dask import started_cluster

tmp = Path(sys.argv[1])
with started_cluster(tmp, {env!r}, ("w1",)) as (address, workers, names):
    (tmp / "ready").write_text(address)
    time.sleep(3600)
"""


def test_the_dask_processes_the_suite_starts_die_with_the_test_process_that_started_them(tmp_path):
    pytest.importorskip("distributed", reason='the dask extra is not installed: pip install "deformlab[dask]"')
    folder = tmp_path / "cluster"
    env = dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}")
    owner = subprocess.Popen([sys.executable, "-c", OWNER.format(env=env), str(folder)], cwd=ROOT, env=env,
                             stdout=subprocess.DEVNULL, stderr=open(tmp_path / "owner.log", "wb"))
    try:
        _wait_for(lambda: (folder / "ready").exists() or owner.poll() is not None, 300, "the suite's cluster to start")
        assert owner.poll() is None, (tmp_path / "owner.log").read_text()[-3000:]
        tree = _tree(owner.pid)
        started = [c for c in tree.values() if any(a.endswith("/dask") for a in c)]
        assert len(started) == 3, started  # the scheduler, w1 and the worker without bubblewrap
        owner.send_signal(signal.SIGKILL)
        owner.wait()
        _wait_for(lambda: not _left(set(tree), folder), PATIENCE, "the scheduler and workers to die with the test process")
    finally:
        if owner.poll() is None:
            owner.kill()
            owner.wait()
