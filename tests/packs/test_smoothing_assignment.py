"""The second assignment (assignments/smoothing), added with no engine change, goes through everything the first does:
release checks, its own bundle, grading with its corpus, report, LMS export and a Gradescope zip (slow: a release)."""

from __future__ import annotations

import csv
import json
import zipfile
from pathlib import Path

import nbformat
import pytest

from grader import course_pack
from grader.build.release import release
from grader.cli import main
from tests.corpus import build_submission, load_corpus, student_id
from grader.gradescope import build_autograder_zip, run
from grader.paths import CoursePaths
from grader.pipeline.run import GradeOptions, grade_class
from tests.course_copy import copy_course_config

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = "00_laplacian_smoothing"
FUNCTIONS = ("uniform_laplacian", "cotangent_matrix", "explicit_smoothing_step", "implicit_smoothing_step")
ENTRIES = load_corpus(ROOT / "tests" / "corpus" / "smoothing")

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    """A private copy of the course (its packs copied, its code linked), released for the smoothing assignment."""
    root = tmp_path_factory.mktemp("smoothing-course")
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    copy_course_config(root / "assignments")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DEFORMLAB_ROOT", str(root))
        course_pack.forget()
        paths = CoursePaths(root)
        yield paths, release(assignment="smoothing", paths=paths)
    course_pack.forget()


@pytest.fixture(scope="module")
def graded(course, tmp_path_factory):
    """The smoothing corpus and the teaching solutions graded as one class."""
    paths, _ = course
    tmp = tmp_path_factory.mktemp("smoothing-class")
    submitted, out = tmp / "submitted", tmp / "out"
    for entry in ENTRIES:
        build_submission(entry, paths.source / "smoothing", submitted, student_id(entry))
    teaching = submitted / "teaching" / "smoothing"
    teaching.mkdir(parents=True)
    nbformat.write(nbformat.read(paths.source / "smoothing" / f"{NOTEBOOK}.ipynb", as_version=4), teaching / f"{NOTEBOOK}.ipynb")
    options = GradeOptions(db_url=f"sqlite:///{tmp}/gradebook.db", progress=False, autograded=tmp / "autograded",
                           assignment="smoothing", seed=11)
    results = grade_class(submitted, out, options, paths)
    return tmp, out, results


def test_the_second_assignment_passes_the_release_checks_of_the_first(course):
    _, report = course
    assert report.problems == [] and report.executed
    assert report.points == {NOTEBOOK: 14.0}


def test_its_bundle_ships_its_own_readme_contract_policy_and_meshes_only(course):
    paths, _ = course
    with zipfile.ZipFile(paths.dist / "smoothing-student.zip") as z:
        names = set(z.namelist())
        readme = z.read("smoothing/README.md").decode()
        policy = z.read("smoothing/LIBRARY_POLICY.md").decode()
    assert readme == (ROOT / "assignments" / "smoothing" / "README.student.md").read_text()
    assert {"smoothing/CONTRACT.md", f"smoothing/{NOTEBOOK}.ipynb", "smoothing/check_notebook.py"} <= names
    assert {n for n in names if n.startswith("smoothing/data/")} == {"smoothing/data/sphere.npz", "smoothing/data/character.npz"}
    assert not any("demo_" in n or "03_arap" in n for n in names), "nothing of the deformation course"
    row = next(line for line in policy.splitlines() if line.startswith("| `uniform_laplacian` |"))
    assert "`igl.adjacency_matrix`" in row and "arap" not in policy


def test_its_corpus_entries_lose_exactly_their_functions_and_the_teaching_solutions_keep_all(graded):
    _, _, results = graded
    scores = {r["student_id"]: {t["function"]: t["score"] == t["points"] for t in r["tests"]} for r in results}
    assert scores["teaching"] == dict.fromkeys(FUNCTIONS, True)
    for entry in ENTRIES:
        lost = {f for f, full in scores[student_id(entry)].items() if not full}
        assert lost == set(entry.loses), (entry.name, lost)


def test_its_report_and_canvas_export_carry_its_rows(graded):
    tmp, out, results = graded
    assert main(["report", str(out), "--assignment", "smoothing"]) == 0
    assert "00_laplacian_smoothing" in (out / "report" / "index.html").read_text()
    assert main(["export", str(out), "--to", "canvas", "--file", str(tmp / "canvas.csv"), "--assignment", "smoothing",
                 "--db", f"sqlite:///{tmp}/gradebook.db"]) == 0
    rows = list(csv.reader((tmp / "canvas.csv").open()))
    assert len(rows) >= len(results) and any("teaching" in row for row in rows)


def test_its_gradescope_zip_grades_a_submission(course, tmp_path):
    paths, _ = course
    zip_path = build_autograder_zip(tmp_path / "smoothing.zip", seed=7, assignment="smoothing")
    with zipfile.ZipFile(zip_path) as z:
        assert json.loads(z.read("gradescope.json"))["assignment"] == "smoothing"
        assert "assignments/smoothing/assignment.toml" in z.namelist()
    root = tmp_path / "autograder"
    (root / "submission").mkdir(parents=True)
    (root / "source").mkdir()
    (root / "source" / "gradescope.json").write_text(json.dumps({"assignment": "smoothing", "seed": 7}))
    source = nbformat.read(paths.source / "smoothing" / f"{NOTEBOOK}.ipynb", as_version=4)
    nbformat.write(source, root / "submission" / f"{NOTEBOOK}.ipynb")
    blank = nbformat.read(paths.release / "smoothing" / f"{NOTEBOOK}.ipynb", as_version=4)
    results = json.loads(run(root).read_text())
    assert {t["name"] for t in results["tests"]} == {f"{NOTEBOOK}: {f}" for f in FUNCTIONS}
    assert results["score"] == 14.0 and results["extra_data"] == {"seed": 7, "assignment": "smoothing"}
    nbformat.write(blank, root / "submission" / f"{NOTEBOOK}.ipynb")
    assert json.loads(run(root).read_text())["score"] == 0
