"""A worker pre-starts each next unit's sandbox, and that sandbox is new and the unit's alone."""

from __future__ import annotations

import os

import nbformat
import pytest

from tests.corpus import student_notebook, teaching_cell
from grader.pipeline.unit import UnitSpec, grade_unit
from grader.sandbox import spares
from grader.sandbox.bwrap import bwrap_available

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

pytestmark = pytest.mark.skipif(not bwrap_available(), reason="bubblewrap is missing or cannot create namespaces on this machine")

# Prepended to a solution cell: what the student's sandbox looks like from inside.
PROBE = """import os, resource
seen = sorted(os.listdir("."))
open("left-by-" + str(os.getpid()), "w").close()
print("PROBE", os.getcwd(), os.readlink("/proc/self/ns/pid"), resource.getrlimit(resource.RLIMIT_AS)[0], seen)
"""


def _probe(result: dict) -> tuple[str, str, int, list[str]]:
    nb = nbformat.reads(result["autograded_notebook"], as_version=4)
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream" and out["text"].startswith("PROBE "):
                _, cwd, ns, limit, rest = out["text"].split(" ", 4)
                return cwd, ns, int(limit), eval(rest)  # noqa: S307 - our own print of a list of names
    raise AssertionError("the probe cell printed nothing")


@pytest.fixture
def spec_of(source_notebooks):
    source = nbformat.read(source_notebooks["00_meshes"], as_version=4)
    submitted = student_notebook(source, {"edges": PROBE + teaching_cell("00_meshes", "edges")})
    text = source_notebooks["00_meshes"].read_text()

    def make(student: str, **limits) -> UnitSpec:
        return UnitSpec(student_id=student, notebook="00_meshes", submission=nbformat.writes(submitted).encode(), source=text, seed=5, **limits)

    return make


def spare_sandbox():
    """This thread's spare, if a pool is open."""
    pool = spares.pool()
    return pool.peek() if pool is not None else None


@pytest.fixture
def prestarting():
    spares.open_pool()
    yield
    spares.close_pool()


def test_each_unit_gets_a_new_sandbox_pre_started_for_it_alone(spec_of, prestarting):
    readonly = [os.path.join(REPO, "data"), os.path.join(REPO, "starter")]
    first = grade_unit(spec_of("ada"), readonly)
    spare = spare_sandbox()
    assert spare is not None and spare.km.is_alive()  # launched while ada's outputs were verified
    assert spare.km._pending_fork is None  # its kernel was forked (if it is) before ada's result was returned
    second = grade_unit(spec_of("bob"), readonly)
    assert first["score"] == second["score"] == first["max_score"]
    (cwd1, ns1, _, seen1), (cwd2, ns2, _, seen2) = _probe(first), _probe(second)
    assert cwd2 == str(spare.ws.work) != cwd1  # bob ran in the sandbox pre-started after ada
    assert ns1 != ns2  # another pid namespace: another bwrap
    assert [n for n in seen1 if n.startswith("left-by-")] == []  # each probe lists its workdir, then writes
    assert [n for n in seen2 if n.startswith("left-by-")] == []  # so a name here could only be ada's
    assert not os.path.exists(cwd1) and not os.path.exists(cwd2)  # both workspaces removed after their unit
    assert spare_sandbox() is not spare and spare_sandbox().ws.work != spare.ws.work  # never handed out twice


def test_a_unit_with_other_limits_gets_a_sandbox_with_its_own_limits(spec_of, prestarting):
    readonly = [os.path.join(REPO, "data"), os.path.join(REPO, "starter")]
    grade_unit(spec_of("ada"), readonly)
    spare = spare_sandbox()
    smaller = 3 * 2**30
    result = grade_unit(spec_of("bob", memory_bytes=smaller), readonly)
    cwd, _, limit, _ = _probe(result)
    assert limit == smaller
    assert cwd != str(spare.ws.work) and not os.path.exists(spare.ws.root)  # the spare was discarded, not reused
    assert not spare.km.is_alive()


def test_turning_pre_start_off_leaves_no_kernel_or_workspace(spec_of):
    readonly = [os.path.join(REPO, "data"), os.path.join(REPO, "starter")]
    spares.open_pool()
    try:
        grade_unit(spec_of("ada"), readonly)
        spare = spare_sandbox()
        assert spare is not None
    finally:
        spares.close_pool()
    assert spare_sandbox() is None
    assert not spare.km.is_alive() and not os.path.exists(spare.ws.root)


def test_a_lone_grade_unit_call_pre_starts_nothing(spec_of):
    grade_unit(spec_of("ada"), [os.path.join(REPO, "data"), os.path.join(REPO, "starter")])
    assert spare_sandbox() is None


def test_a_spare_belongs_to_the_thread_that_launched_it(spec_of, prestarting):
    import threading

    readonly = [os.path.join(REPO, "data"), os.path.join(REPO, "starter")]
    grade_unit(spec_of("ada"), readonly)
    mine = spare_sandbox()
    seen = []
    other = threading.Thread(target=lambda: seen.append(spare_sandbox()))
    other.start()
    other.join()
    assert mine is not None and seen == [None]  # another grading thread never gets this thread's kernel
