"""A cell that hangs or kills its kernel costs only itself; the rest of the notebook is still graded."""

import time

import nbformat
import numpy as np

from grader.harness.fixtures import Case, write_fixtures
from grader.harness.outputs import read_outputs
from grader.pipeline.execute import ExecuteOptions, execute


def notebook(*sources):
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(s) for s in sources]
    return nb


def run(tmp_path, nb, functions, timeout=5.0):
    workdir = tmp_path / "w"
    (workdir / "outputs").mkdir(parents=True)
    for f in functions:
        write_fixtures(f, [Case.call("one", f, np.ones(3))], workdir / "fixtures")
    result = execute(nb, list(range(len(nb.cells))), functions, workdir, workdir / "fixtures", workdir / "outputs",
                     ExecuteOptions(timeout=timeout, memory_bytes=2 * 2**30))
    return result, workdir


def test_a_hanging_cell_that_ignores_sigint_is_killed_and_later_cells_still_run(tmp_path):
    nb = notebook(
        "import signal\nsignal.signal(signal.SIGINT, signal.SIG_IGN)\ndef good(x):\n    return x * 2",
        "while True:\n    pass",
        "def other(x):\n    return x + 1",
    )
    start = time.monotonic()
    result, workdir = run(tmp_path, nb, ["good", "other"], timeout=3)
    assert time.monotonic() - start < 60
    assert "timed out" in result.cell_failures[1]
    assert not result.collection_failures
    good = read_outputs("good", workdir / "outputs", 1).cases[0]
    np.testing.assert_array_equal(good.value, [2, 2, 2])  # defined before the hang, replayed after the restart
    np.testing.assert_array_equal(read_outputs("other", workdir / "outputs", 1).cases[0].value, [2, 2, 2])


def test_a_function_that_kills_the_kernel_loses_only_its_own_collection(tmp_path):
    nb = notebook("import os\ndef bad(x):\n    os._exit(1)\ndef good(x):\n    return -x")
    result, workdir = run(tmp_path, nb, ["bad", "good"])
    assert "kernel died" in result.collection_failures["bad"]
    np.testing.assert_array_equal(read_outputs("good", workdir / "outputs", 1).cases[0].value, [-1, -1, -1])


def test_a_timed_out_collection_is_a_failure_never_a_pass(tmp_path):
    nb = notebook("import time\ndef slow(x):\n    time.sleep(60)\n    return x")
    result, workdir = run(tmp_path, nb, ["slow"], timeout=2)
    assert "timed out" in result.collection_failures["slow"]


def test_memory_blowups_stay_inside_the_kernel(tmp_path):
    nb = notebook("import numpy as np\ndef big(x):\n    return np.ones(10 * 2**30 // 8)")
    result, workdir = run(tmp_path, nb, ["big"])
    out = read_outputs("big", workdir / "outputs", 1).cases[0]
    assert out.error is not None and "MemoryError" in out.error


def test_the_notebook_wall_limit_stops_cells_that_each_stay_under_the_cell_timeout(tmp_path):
    nb = notebook("import time\ntime.sleep(2)", "time.sleep(2)", "time.sleep(2)", "def late(x):\n    return x")
    workdir = tmp_path / "w"
    (workdir / "outputs").mkdir(parents=True)
    write_fixtures("late", [Case.call("one", "late", np.ones(3))], workdir / "fixtures")
    result = execute(nb, list(range(4)), ["late"], workdir, workdir / "fixtures", workdir / "outputs",
                     ExecuteOptions(timeout=10, wall=3, memory_bytes=2 * 2**30))
    assert "wall-clock limit" in result.collection_failures["late"]
    assert result.seconds < 15


def test_executing_notebook_after_notebook_leaves_no_descriptor_or_thread_behind(tmp_path):
    # A grading worker runs thousands of units: what one kernel life opens must close with it.
    import os
    import threading

    nb = notebook("import os\ndef bad(x):\n    os._exit(1)\ndef good(x):\n    return -x")  # two kernel lives each
    counts = []
    for k in range(4):
        run(tmp_path / str(k), nb, ["bad", "good"])
        counts.append((len(os.listdir("/proc/self/fd")), threading.active_count()))
    assert counts[1] == counts[2] == counts[3], counts
