"""After ``deformlab demo``, formgrader (nbgrader's API, which its pages show) sees the demo class as a course's.

The demo's own steps on a course of one notebook (01): the class written where
nbgrader's collect puts it, graded into the course's gradebook, then names, the
due date and the release. Before, formgrader showed an empty gradebook, students
as "None, None", "# Submissions 0" and the assignment as "draft".
"""

from __future__ import annotations

import shutil

import pytest

from grader.contract import ASSIGNMENT
from grader.paths import CoursePaths

from .conftest import ROOT


@pytest.fixture(scope="module")
def demo_course(source_notebooks, tmp_path_factory):
    from grader.build.release import generate_assignment
    from grader.demo import build_class, show_in_formgrader
    from grader.pipeline.run import GradeOptions, grade_class

    root = tmp_path_factory.mktemp("demo-course")
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    paths = CoursePaths(root)
    (paths.source / ASSIGNMENT).mkdir(parents=True)
    shutil.copy(source_notebooks["01_shape_matching"], paths.source / ASSIGNMENT)
    exchange = root / "exchange"
    exchange.mkdir()
    config = (ROOT / "assignments" / "nbgrader_config.py").read_text()
    (paths.course / "nbgrader_config.py").write_text(config + f"\nc.Exchange.root = {str(exchange)!r}\n")
    generate_assignment(paths, ASSIGNMENT)
    submitted = paths.course / "submitted"
    (submitted / "someone_else" / ASSIGNMENT).mkdir(parents=True)  # a real student's folder, which the demo leaves alone
    students = build_class(submitted, paths.source_notebooks(ASSIGNMENT), paths.release / ASSIGNMENT, [])
    out = root / "demo-out"
    grade_class(submitted, out, GradeOptions(workers=2, seed=3, progress=False), paths)
    notes = show_in_formgrader(paths, out, submitted, paths.gradebook_url, students)
    return paths, students, notes


def formgrader_api(paths):
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from traitlets.config.loader import PyFileConfigLoader

    config = PyFileConfigLoader("nbgrader_config.py", path=str(paths.course)).load_config()
    config.CourseDirectory.root = str(paths.course)
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
