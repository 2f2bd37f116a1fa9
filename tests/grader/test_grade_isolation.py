"""One student's notebook cannot cost another theirs: a dead worker blames only its culprit, runs never share an OUT."""

from __future__ import annotations

import csv
import fcntl
import json
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool

import nbformat
import pytest

from grader.paths import CoursePaths
from grader.pipeline import local_pool
from grader.pipeline.run import GradeOptions, GradingInProgress, grade_class
from tests.grader.standin_units import CULPRIT, kills_its_worker_for_the_culprit

STUDENTS = ["ada", "bob", CULPRIT, "dan", "eve", "fay", "gus"]


@pytest.fixture
def submitted(tmp_path, source_notebooks):
    folder = tmp_path / "submitted"
    for sid in STUDENTS:
        (folder / sid / "deformation").mkdir(parents=True)
        nbformat.write(nbformat.v4.new_notebook(), folder / sid / "deformation" / "00_meshes.ipynb")
    return folder


def _options(tmp_path, **kw):
    return GradeOptions(workers=2, db_url=f"sqlite:///{tmp_path}/gb.db", seed=3, progress=False, **kw)


def test_a_worker_killed_mid_unit_costs_only_the_culprit_and_every_unit_is_recorded_once(tmp_path, submitted, make_course):
    out = tmp_path / "out"
    paths = CoursePaths(make_course(tmp_path))
    results = grade_class(submitted, out, _options(tmp_path), paths, grade=kills_its_worker_for_the_culprit)
    rows = list(csv.DictReader(open(out / "grades.csv")))
    assert len(rows) == len({(r["student_id"], r["notebook"]) for r in rows}) == len(STUDENTS) * len({r["notebook"] for r in rows})
    blamed = {(r["student_id"], r["notebook"]) for r in results if r["status"] == "grader-error"}
    assert blamed == {(CULPRIT, "00_meshes")}
    culprit = next(r for r in results if r["status"] == "grader-error")
    assert "died" in culprit["reasons"][0]
    log = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    assert sorted((r["student_id"], r["notebook"]) for r in log) == sorted((r["student_id"], r["notebook"]) for r in results)


def test_a_second_run_into_the_same_out_is_refused_while_the_first_holds_it(tmp_path, submitted):
    out = tmp_path / "out"
    out.mkdir()
    with open(out / ".grading.lock", "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        with pytest.raises(GradingInProgress, match="another `deformlab grade` is writing"):
            grade_class(submitted, out, _options(tmp_path), CoursePaths(tmp_path / "nowhere"), grade=kills_its_worker_for_the_culprit)
    assert not (out / "grades.csv").exists()


class _PoolBrokenAfter:
    """A stand-in executor that runs units at once, until a worker "dies" before its ``breaks_at``-th submission.

    As in ``concurrent.futures``, a broken pool refuses every later ``submit`` with
    ``BrokenProcessPool``, while the results it already returned stand.
    """

    def __init__(self, breaks_at: int | None):
        self.breaks_at, self.submitted = breaks_at, 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def submit(self, fn, *args):
        if self.breaks_at is not None and self.submitted >= self.breaks_at:
            raise BrokenProcessPool("A child process terminated abruptly, the process pool is not usable anymore")
        self.submitted += 1
        future = Future()
        future.set_result(fn(*args))
        return future


def test_a_pool_that_breaks_between_two_submissions_loses_no_unit(monkeypatch):
    # The race behind a rare "BrokenProcessPool" escaping grade_class: a worker died after
    # the last wait returned only finished units, and the next submit found the pool broken.
    pools = iter([_PoolBrokenAfter(3), _PoolBrokenAfter(None)])
    monkeypatch.setattr(local_pool, "_pool", lambda workers: next(pools))
    units = [f"unit{k}" for k in range(7)]
    graded = list(local_pool.grade_in_pool(units, lambda unit: unit, lambda unit, reason: {"error": reason}, 2, [], lambda spec, readonly: {"graded": spec}))
    assert sorted(unit for unit, _ in graded) == units
    assert all(result == {"graded": unit} for unit, result in graded)
