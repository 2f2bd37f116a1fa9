"""After ``make demo``, formgrader (nbgrader's API, which its pages show) sees the demo class as a course's.

The demo's own steps on a course of one notebook (01): the class written where
nbgrader's collect puts it, graded into the course's gradebook, then names, the
due date and the release. Before, formgrader showed an empty gradebook, students
as "None, None", "# Submissions 0" and the assignment as "draft".
"""

from __future__ import annotations

import shutil

import pytest
from tests.course_copy import copy_course_config

ASSIGNMENT = "deformation"
from grader.paths import CoursePaths

from .conftest import ROOT


@pytest.fixture(scope="module")
def demo_course(source_notebooks, tmp_path_factory):
    from grader.gradebook import generate_assignment
    from tests.demo import build_class, show_in_formgrader
    from grader.pipeline.run import GradeOptions, grade_class

    root = tmp_path_factory.mktemp("demo-course")
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    paths = CoursePaths(root)
    (paths.source / ASSIGNMENT).mkdir(parents=True)
    shutil.copy(source_notebooks["01_shape_matching"], paths.source / ASSIGNMENT)
    exchange = root / "exchange"
    exchange.mkdir()
    copy_course_config(paths.course, f"\nc.Exchange.root = {str(exchange)!r}\n")
    generate_assignment(paths, ASSIGNMENT)
    submitted = paths.course / "submitted"
    (submitted / "someone_else" / ASSIGNMENT).mkdir(parents=True)  # a real student's folder, which the demo leaves alone
    students = build_class(submitted, paths.source_notebooks(ASSIGNMENT), paths.release / ASSIGNMENT, [])
    out = root / "demo-out"
    grade_class(submitted, out, GradeOptions(workers=2, seed=3, progress=False), paths)
    notes = show_in_formgrader(paths, out, submitted, paths.gradebook_url, students)
    return paths, students, notes


def formgrader_api(paths, stock_feedback: bool = False):
    """nbgrader's API with the course's nbgrader_config.py (``stock_feedback``: with generate_feedback's default preprocessors)."""
    from nbconvert.preprocessors import CSSHTMLHeaderPreprocessor
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from nbgrader.preprocessors import GetGrades
    from traitlets.config.loader import PyFileConfigLoader

    config = PyFileConfigLoader("nbgrader_config.py", path=str(paths.course)).load_config()
    config.CourseDirectory.root = str(paths.course)
    if stock_feedback:
        config.GenerateFeedback.preprocessors = [GetGrades, CSSHTMLHeaderPreprocessor]
    return NbGraderAPI(coursedir=CourseDirectory(config=config), config=config)


def test_formgrader_lists_the_demo_class_with_names_and_every_submission_autograded(demo_course):
    paths, students, notes = demo_course
    api = formgrader_api(paths)
    assert students == ["reference", "blank"] and (paths.course / "submitted" / "someone_else").is_dir()
    assignment = api.get_assignment(ASSIGNMENT)
    assert assignment["num_submissions"] == 3 and assignment["status"] == "released", notes
    people = {s["id"]: s for s in api.get_students()}
    assert all((people[sid]["first_name"], people[sid]["last_name"]) == (sid, "Demo") for sid in students)
    subs = {s["student"]: s for s in api.get_submissions(ASSIGNMENT)}
    assert all(subs[sid]["autograded"] for sid in students)
    assert subs["reference"]["score"] > 0 and subs["reference"]["needs_manual_grade"]
    assert subs["blank"]["display_timestamp"] and subs["blank"]["score"] == 0


def test_the_demos_late_student_carries_the_late_policy_into_the_gradebook(demo_course):
    from nbgrader.api import Gradebook

    paths, _, _ = demo_course
    with Gradebook(paths.gradebook_url) as gb:
        assert gb.find_submission(ASSIGNMENT, "blank").total_seconds_late == 26 * 3600
        assert gb.find_submission(ASSIGNMENT, "reference").total_seconds_late == 0


def test_formgraders_notebook_shows_the_model_answer_and_a_rubric_after_each_written_answer(demo_course):
    import nbformat

    paths, _, _ = demo_course
    source = nbformat.read(paths.source / ASSIGNMENT / "01_shape_matching.ipynb", as_version=4)
    answers = [(c.metadata.nbgrader["grade_id"], c.source, c.metadata.nbgrader["points"]) for c in source.cells
               if c.cell_type == "markdown" and (c.metadata.get("nbgrader") or {}).get("grade")]
    assert answers
    for sid in ("reference", "blank"):
        nb = nbformat.read(paths.course / "autograded" / sid / ASSIGNMENT / "01_shape_matching.ipynb", as_version=4)
        nbformat.validate(nb)
        ids = [(c.metadata.get("nbgrader") or {}).get("grade_id") for c in nb.cells]
        for grade_id, model, points in answers:
            note = nb.cells[ids.index(grade_id) + 1]
            assert note.metadata.tags == ["deformlab-ta-only"] and "nbgrader" not in note.metadata
            assert f"**Model answer** ({points:g} points):" in note.source
            assert all(f"> {line}" in note.source for line in model.splitlines() if line.strip())
            assert f"- **{points:g}**: the conclusion and the reasoning" in note.source and "- **0**: no answer" in note.source


def test_nbgraders_generate_feedback_with_the_courses_config_never_returns_the_model_answer(demo_course):
    paths, _, _ = demo_course
    result = formgrader_api(paths).generate_feedback(ASSIGNMENT, "blank")
    assert result["success"], result.get("log")
    page = (paths.course / "feedback" / "blank" / ASSIGNMENT / "01_shape_matching.html").read_text()
    assert "YOUR ANSWER HERE" in page  # the student's own (blank) answer is there
    assert "Model answer" not in page and "For the TA" not in page
    # Control: nbgrader's stock preprocessors would return it (so the course's configuration is what keeps it back).
    assert formgrader_api(paths, stock_feedback=True).generate_feedback(ASSIGNMENT, "reference")["success"]
    assert "Model answer" in (paths.course / "feedback" / "reference" / ASSIGNMENT / "01_shape_matching.html").read_text()
