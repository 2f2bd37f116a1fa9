"""The bonus notebook (06_fast) is extra credit in nbgrader's gradebook, formgrader's API and ``nbgrader export``.

A real gradebook from nbgrader's own ``generate_assignment`` on the real source
notebooks of 01 and 06, and unit results recorded as a grading run records them.
"""

from __future__ import annotations

import csv
import shutil

import nbformat
import pytest

ASSIGNMENT = "deformation"
from grader.pipeline import record
from grader.pipeline.verify import graded_cells
from grader.paths import CoursePaths

from .conftest import ROOT

NOTEBOOKS = ("01_shape_matching", "06_fast")


def unit_result(sid: str, notebook: str, source: nbformat.NotebookNode, fraction: float) -> dict:
    """A graded unit as ``grade_unit`` returns it: every tests cell at ``fraction`` of its points."""
    tests = [{"grade_id": c.grade_id, "function": c.function, "points": c.points, "score": c.points * fraction}
             for c in graded_cells(source)]
    return {"student_id": sid, "assignment": ASSIGNMENT, "notebook": notebook, "status": "graded", "tests": tests,
            "score": sum(t["score"] for t in tests), "max_score": sum(t["points"] for t in tests)}


@pytest.fixture(scope="module")
def bonus_course(source_notebooks, tmp_path_factory):
    """``(paths, db_url, sources)``: a course of 01 and 06 whose gradebook holds ada (full marks) and bob (half of 01, a quarter of 06)."""
    from grader.gradebook import generate_assignment

    root = tmp_path_factory.mktemp("bonus-course")
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    target = root / "assignments" / "source" / ASSIGNMENT
    target.mkdir(parents=True)
    for nb in NOTEBOOKS:
        shutil.copy(source_notebooks[nb], target)
    paths = CoursePaths(root)
    db = f"sqlite:///{root}/gradebook.db"
    generate_assignment(paths, ASSIGNMENT, db)
    sources = {nb: nbformat.read(target / f"{nb}.ipynb", as_version=4) for nb in NOTEBOOKS}
    for sid in ("ada", "bob"):  # formgrader lists what was submitted and has an autograded notebook
        (root / "assignments" / "submitted" / sid / ASSIGNMENT).mkdir(parents=True)
        for nb in NOTEBOOKS:
            record.write_autograded(root / "assignments" / "autograded", {
                "student_id": sid, "assignment": ASSIGNMENT, "notebook": nb, "autograded_notebook": nbformat.writes(sources[nb])})
    with record.open_gradebook(db) as gb:
        for sid, fractions in (("ada", (1.0, 1.0)), ("bob", (0.5, 0.25))):
            for nb, fraction in zip(NOTEBOOKS, fractions):
                record.record_gradebook(gb, unit_result(sid, nb, sources[nb], fraction))
    return paths, db, sources


def points(source, kind: str) -> float:
    """A source notebook's autograded (``code``) or hand-graded (``markdown``) points."""
    return sum(float(c.metadata["nbgrader"]["points"]) for c in source.cells
               if c.cell_type == kind and (c.metadata.get("nbgrader") or {}).get("grade"))


def test_bonus_points_are_extra_credit_in_the_gradebook(bonus_course):
    _, db, sources = bonus_course
    regular_max = points(sources["01_shape_matching"], "code") + points(sources["01_shape_matching"], "markdown")
    bonus_max = points(sources["06_fast"], "code")
    assert bonus_max > 0
    with record.open_gradebook(db) as gb:
        assert gb.find_assignment(ASSIGNMENT).max_score == pytest.approx(regular_max)
        ada, bob = gb.find_submission(ASSIGNMENT, "ada"), gb.find_submission(ASSIGNMENT, "bob")
        assert ada.score == pytest.approx(points(sources["01_shape_matching"], "code") + bonus_max)
        assert bob.score == pytest.approx(0.5 * points(sources["01_shape_matching"], "code") + 0.25 * bonus_max)
        fast = gb.find_submission_notebook("06_fast", ASSIGNMENT, "bob")
        assert fast.max_score == 0 and fast.score == pytest.approx(0.25 * bonus_max)
        assert {g.auto_score for g in fast.grades if g.cell_type == "code"} == {0.0}
        # A TA's grading of the bonus written answer is extra credit too: its cell is worth 0.
        assert [g.max_score for g in fast.grades if g.cell_type == "markdown"] == [0]


def test_formgrader_shows_the_bonus_above_the_regular_maximum(bonus_course):
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from traitlets.config import Config

    paths, db, sources = bonus_course
    config = Config()
    config.CourseDirectory.root = str(paths.course)
    config.CourseDirectory.db_url = db
    api = NbGraderAPI(coursedir=CourseDirectory(config=config), config=config)
    regular_max = points(sources["01_shape_matching"], "code") + points(sources["01_shape_matching"], "markdown")
    assert api.get_assignment(ASSIGNMENT)["max_score"] == pytest.approx(regular_max)
    ada = api.get_submission(ASSIGNMENT, "ada")
    assert ada["max_score"] == pytest.approx(regular_max)
    assert ada["score"] == pytest.approx(points(sources["01_shape_matching"], "code") + points(sources["06_fast"], "code"))
    fast = {nb["student"]: nb for nb in api.get_notebook_submissions(ASSIGNMENT, "06_fast")}
    assert fast["bob"]["max_score"] == 0 and fast["bob"]["score"] == pytest.approx(0.25 * points(sources["06_fast"], "code"))


def test_nbgrader_export_counts_the_bonus_in_the_score_not_the_maximum(bonus_course, tmp_path, monkeypatch):
    from nbgrader.api import Gradebook
    from nbgrader.plugins import CsvExportPlugin

    _, db, sources = bonus_course
    monkeypatch.chdir(tmp_path)
    with Gradebook(db) as gb:
        CsvExportPlugin(to="grades.csv").export(gb)
    with open(tmp_path / "grades.csv", newline="") as fh:
        rows = {r["student_id"]: r for r in csv.DictReader(fh)}
    regular_max = points(sources["01_shape_matching"], "code") + points(sources["01_shape_matching"], "markdown")
    assert float(rows["ada"]["max_score"]) == pytest.approx(regular_max)
    assert float(rows["ada"]["score"]) == pytest.approx(points(sources["01_shape_matching"], "code") + points(sources["06_fast"], "code"))


def test_regrading_keeps_the_bonus_cells_at_zero_after_generate_assignment_reset_them(bonus_course):
    from grader.gradebook import generate_assignment

    paths, db, sources = bonus_course
    generate_assignment(paths, ASSIGNMENT, db)  # `deformlab release` writes the notebook's points again
    with record.open_gradebook(db) as gb:
        assert gb.find_notebook("06_fast", ASSIGNMENT).max_score > 0
        record.record_gradebook(gb, unit_result("ada", "06_fast", sources["06_fast"], 1.0))
        assert gb.find_notebook("06_fast", ASSIGNMENT).max_score == 0
        assert gb.find_submission(ASSIGNMENT, "ada").score == pytest.approx(
            points(sources["01_shape_matching"], "code") + points(sources["06_fast"], "code"))
