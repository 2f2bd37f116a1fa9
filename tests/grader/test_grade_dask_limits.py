"""On a Dask worker, verification and feedback run under the grader's own limits, as in the process pool.

Dask runs tasks in worker threads, where ``grader_limits`` cannot hold (its alarm
reaches the main thread only); so each worker thread grades in a grading process
of its own. A real local cluster (``--scheduler local:1``: a nanny and a worker
process) grades a real buggy submission while a probe records, inside the
grader's own code, whether the limits were in force each time they were entered.
"""

from __future__ import annotations

import os
import resource

import pytest

from tests.corpus import build_submission, load_entry
from grader.pipeline.distributed import GradingProcessDied, connect, grade_unit_on_worker, on_grading_process
from grader.pipeline.guard import DEFAULT_GRADER_MEMORY_BYTES, DEFAULT_GRADER_SECONDS
from grader.pipeline.unit import UnitSpec

distributed = pytest.importorskip("distributed", reason='the dask extra is not installed: pip install "deformlab[dask]"')
pytestmark = [pytest.mark.slow, pytest.mark.filterwarnings("ignore::nbformat.warnings.DuplicateCellId")]

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.fixture(scope="module")
def client():
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DEFORMLAB_ROOT", ROOT)  # the workers inherit it: the course kit of this checkout
        client, cluster = connect("local:1")
    yield client
    client.close()
    cluster.close()


def limits_here() -> dict:
    """What ``grader_limits`` gives the calling thread."""
    import resource
    import signal

    from grader.pipeline.guard import grader_limits

    with grader_limits() as active:
        return {"active": active, "rlimit_as": resource.getrlimit(resource.RLIMIT_AS)[0], "alarm": signal.getitimer(signal.ITIMER_REAL)[0]}


def test_a_dask_task_thread_cannot_hold_the_grader_limits(client):
    # why the grading process exists: the same block in the task's own thread runs without them
    assert client.submit(limits_here, pure=False).result() == {"active": False, "rlimit_as": resource.RLIM_INFINITY, "alarm": 0.0}


def test_verification_and_feedback_on_a_dask_worker_run_under_the_grader_limits(client, source_notebooks, tmp_path):
    entry = load_entry(os.path.join(ROOT, "tests", "corpus", "buggy", "no_sign_correction.py"))
    path = build_submission(entry, source_notebooks[entry.notebook].parent, tmp_path, "bob")
    spec = UnitSpec(student_id="bob", notebook=entry.notebook, submission=path.read_bytes(),
                    source=source_notebooks[entry.notebook].read_text(), seed=7, timeout=300)  # a busy machine's cells too

    def probed_grade(spec):
        # Runs where the worker grades: records each grader_limits block of grade_unit as it is entered.
        import contextlib
        import resource
        import signal
        import threading

        import grader.pipeline.unit as unit
        from grader.sandbox.limits import status_bytes

        seen, original = [], unit.grader_limits

        @contextlib.contextmanager
        def recording(*args, **kwargs):
            before = status_bytes(os.getpid(), "VmSize")
            with original(*args, **kwargs) as active:
                seen.append({"active": active, "main_thread": threading.current_thread() is threading.main_thread(),
                             "rlimit_as": resource.getrlimit(resource.RLIMIT_AS)[0], "vm_size": before,
                             "alarm": signal.getitimer(signal.ITIMER_REAL)[0]})
                yield active

        unit.grader_limits = recording
        try:
            return unit.grade_unit(spec), seen, os.getpid()
        finally:
            unit.grader_limits = original

    result, seen, grader_pid = client.submit(grade_unit_on_worker, spec, False, probed_grade, pure=False).result()
    assert result["status"] == "graded" and 0 < result["score"] < result["max_score"], result["reasons"] + result["events"]
    failed = [t["function"] for t in result["tests"] if t["score"] < t["points"]]
    assert "optimal_rotation" in failed
    # one block per graded function (verification) and one for the feedback page
    assert len(seen) == len(result["tests"]) + 1
    for block in seen:
        assert block["active"] and block["main_thread"], seen
        # the cap is the process's size when the block starts plus 2 GiB (another thread, the next
        # unit's sandbox launch, may map or unmap memory between the probe's reading and the guard's)
        assert abs(block["rlimit_as"] - (block["vm_size"] + DEFAULT_GRADER_MEMORY_BYTES)) < 256 * 2**20, seen
        assert 0 < block["alarm"] <= DEFAULT_GRADER_SECONDS, seen
    worker_pids = client.run(os.getpid)
    assert grader_pid not in worker_pids.values()
    # the next unit of this worker thread is graded by the same grading process
    assert client.submit(on_grading_process, os.getpid, pure=False).result() == grader_pid


def test_a_grading_process_that_dies_costs_only_its_unit(client):
    pid = client.submit(on_grading_process, os.getpid, pure=False).result()
    with pytest.raises(GradingProcessDied, match="the grading process died while grading this notebook"):
        client.submit(on_grading_process, os._exit, 9, pure=False).result()
    # a new grading process takes the next unit
    assert client.submit(on_grading_process, os.getpid, pure=False).result() not in (pid, None)


def test_a_unit_whose_grading_process_dies_once_is_graded_again_and_twice_is_a_grader_error(client, tmp_path):
    marker = tmp_path / "died-once"

    def dies_the_first_time(spec):
        if not marker.exists():
            marker.touch()
            os._exit(9)
        return {"graded_by": os.getpid()}

    def always_dies(spec):
        os._exit(9)

    result = client.submit(grade_unit_on_worker, None, False, dies_the_first_time, pure=False).result()
    assert marker.exists() and result["graded_by"] == client.submit(on_grading_process, os.getpid, pure=False).result()
    with pytest.raises(GradingProcessDied, match=r"died while grading this notebook \(exit status 9\), twice"):
        client.submit(grade_unit_on_worker, None, False, always_dies, pure=False).result()
