"""A third assignment added from a folder outside the kit (tests/packs/tiny_pack, one function) builds, releases,
grades, reports and exports, and no engine file changes for it (slow: a release)."""

from __future__ import annotations

import csv
import shutil
import subprocess
from pathlib import Path

import nbformat
import pytest

from grader import course_pack
from grader.build.release import release
from grader.cli import main
from tests.corpus import student_notebook
from grader.paths import CoursePaths
from grader.pipeline.run import GradeOptions, grade_class

ROOT = Path(__file__).resolve().parents[2]
TINY = Path(__file__).resolve().parent / "tiny_pack"

pytestmark = pytest.mark.slow


def _engine_state() -> str:
    """``git status`` of grader/: what the working tree changed there (empty on a clean checkout)."""
    done = subprocess.run(["git", "status", "--porcelain", "--", "grader"], cwd=ROOT, capture_output=True, text=True)
    return done.stdout if done.returncode == 0 else "no git"


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    """A course whose only assignment is the tiny pack, configured by one setting of nbgrader_config.py."""
    before = _engine_state()
    tmp = tmp_path_factory.mktemp("tiny")
    pack_folder = shutil.copytree(TINY, tmp / "packs" / "areas")
    root = tmp / "course"
    for name in ("data", "notebooks", "starter"):
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).symlink_to(ROOT / name)
    (root / "assignments").mkdir()
    (root / "assignments" / "nbgrader_config.py").write_text(
        "from pathlib import Path\n"
        "c = get_config()\n"
        "c.CourseDirectory.root = str(Path(__file__).resolve().parent)\n"
        "c.CourseDirectory.course_id = 'deformlab'\n"
        f"c.DeformLab.course_packs = [{str(pack_folder)!r}]\n"
    )
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DEFORMLAB_ROOT", str(root))
        course_pack.forget()
        paths = CoursePaths(root)
        yield tmp, paths, release(assignment="areas", paths=paths), before
    course_pack.forget()


def test_the_new_pack_is_the_course_s_only_assignment_and_passes_every_release_check(course):
    _, paths, report, _ = course
    assert list(course_pack.packs()) == ["areas"] and course_pack.default_assignment() == "areas"
    assert report.problems == [] and report.executed
    assert report.points == {"00_areas": 2.0}
    source = nbformat.read(paths.source / "areas" / "00_areas.ipynb", as_version=4)
    assert source.metadata["deformlab"] == {"notebook": "00_areas", "assignment": "areas", "bonus": False,
                                            "functions": ["triangle_areas"]}
    policy_cell = next(c for c in source.cells if "library_policy.declare(" in c.source)
    assert "'triangle_areas': ['igl.doublearea']" in policy_cell.source


def test_it_grades_reports_and_exports_with_no_engine_file_changed(course):
    tmp, paths, _, before = course
    source = nbformat.read(paths.source / "areas" / "00_areas.ipynb", as_version=4)
    submitted = tmp / "submitted"
    blank = nbformat.read(paths.release / "areas" / "00_areas.ipynb", as_version=4)
    for sid, nb in (("teaching", source), ("blank", blank),
                    ("shortcut", student_notebook(source, {"triangle_areas": "import igl\n\n\ndef triangle_areas(V, F):\n"
                                                                              "    return igl.doublearea(V, F) / 2\n"}))):
        (submitted / sid / "areas").mkdir(parents=True)
        nbformat.write(nb, submitted / sid / "areas" / "00_areas.ipynb")
    out = tmp / "out"
    results = grade_class(submitted, out, GradeOptions(db_url=f"sqlite:///{tmp}/gb.db", progress=False,
                                                       autograded=tmp / "autograded"), paths)
    scores = {r["student_id"]: r["score"] for r in results}
    assert scores == {"teaching": 2.0, "blank": 0.0, "shortcut": 0.0}
    shortcut = next(r for r in results if r["student_id"] == "shortcut")
    assert "igl.doublearea" in shortcut["tests"][0]["summary"], "the pack's library policy is enforced when grading"
    hint = "Hint from the course: check a mesh with a zero-area (degenerate) triangle first."
    notes = {r["student_id"]: r.get("notes", []) for r in results}
    assert hint in notes["shortcut"] and hint in notes["blank"] and hint not in notes["teaching"], "the pack's own step ran"
    assert hint in (out / "feedback" / "shortcut" / "00_areas.html").read_text()
    assert main(["report", str(out)]) == 0 and "00_areas" in (out / "report" / "index.html").read_text()
    assert main(["export", str(out), "--to", "moodle", "--file", str(tmp / "moodle.csv"), "--db", f"sqlite:///{tmp}/gb.db"]) == 0
    assert len(list(csv.reader((tmp / "moodle.csv").open()))) == 1 + 3
    assert _engine_state() == before, "adding an assignment changed files of grader/"
