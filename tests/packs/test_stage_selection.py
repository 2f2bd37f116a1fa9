"""An instructor includes a subset of an assignment's stages with one setting (``c.DeformLab.stages``): building,
the release checks, the bundle, grading, the report and the exports follow it; a wrong setting is refused naming
the file and the setting (slow: a release and a graded class of two notebooks)."""

from __future__ import annotations

import csv
import zipfile
from pathlib import Path

import nbformat
import pytest

from grader import course_pack
from grader.build.release import release
from grader.cli import main
from grader.course_pack import PackError
from grader.paths import CoursePaths
from grader.pipeline.run import GradeOptions, grade_class
from tests.course_copy import copy_course_config

ROOT = Path(__file__).resolve().parents[2]
# given out of teaching order on purpose: the assignment keeps the pack's order
CHOSEN = ["02_sign_correction", "01_shape_matching"]


def _course(root: Path, setting: str) -> CoursePaths:
    root.mkdir()
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    copy_course_config(root / "assignments", setting)
    return CoursePaths(root)


@pytest.fixture
def configured(tmp_path, monkeypatch):
    """A course folder configured by ``setting``, appended to the checkout's nbgrader_config.py."""

    def make(setting: str) -> CoursePaths:
        paths = _course(tmp_path / "course", setting)
        monkeypatch.setenv("DEFORMLAB_ROOT", str(paths.root))
        course_pack.forget()
        return paths

    yield make
    course_pack.forget()


def test_the_assignment_has_only_the_chosen_stages_in_teaching_order(configured):
    configured(f"c.DeformLab.stages = {{'deformation': {CHOSEN!r}}}\n")
    deformation = course_pack.pack("deformation")
    assert deformation.stage_names == ("01_shape_matching", "02_sign_correction")
    assert deformation.functions == ("centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align",
                                     "optimal_rotation", "rigid_align")
    assert course_pack.pack("smoothing").stage_names == ("00_laplacian_smoothing",), "other assignments keep every stage"


@pytest.mark.parametrize(
    ("setting", "named"),
    [
        ("c.DeformLab.stages = {'deformation': ['01_shape_matching', '09_nowhere']}", "'09_nowhere', which is not a stage of deformation"),
        ("c.DeformLab.stages = {'geometry': ['00_meshes']}", "'geometry', which is not an assignment of the course"),
        ("c.DeformLab.stages = {'deformation': ['00_meshes', '00_meshes']}", "names a stage twice"),
        ("c.DeformLab.stages = {'deformation': []}", "stages"),
        ("c.DeformLab.stages = ['00_meshes']", "stages"),
        ("c.DeformLab.stage = {'deformation': ['00_meshes']}", "c.DeformLab.stage is not a setting of the kit"),
    ],
)
def test_a_wrong_setting_is_refused_naming_the_file_and_the_setting(configured, setting, named):
    paths = configured(setting + "\n")
    with pytest.raises(PackError) as refused:
        course_pack.pack("deformation")
    assert str(paths.course / "nbgrader_config.py") in str(refused.value)
    assert named in str(refused.value)


@pytest.mark.slow
def test_release_grading_report_and_exports_follow_the_chosen_stages(configured, tmp_path):
    paths = configured(f"c.DeformLab.stages = {{'deformation': {CHOSEN!r}}}\n")
    (paths.source / "deformation").mkdir(parents=True)
    (paths.source / "deformation" / "05_lbs.ipynb").write_text("{}")  # built before the course dropped the stage
    # not executed here: the grading below is the release's own check (teaching solutions full marks, blank 0)
    report = release(assignment="deformation", execute=False, paths=paths)
    assert report.problems == []
    assert set(report.points) == {"01_shape_matching", "02_sign_correction"}
    assert [p.stem for p in paths.source_notebooks("deformation")] == ["01_shape_matching", "02_sign_correction"]
    assert sorted(p.name for p in (paths.release / "deformation").glob("*.ipynb")) == ["01_shape_matching.ipynb",
                                                                                      "02_sign_correction.ipynb"]
    bundle = next(paths.dist.glob("*.zip"))
    with zipfile.ZipFile(bundle) as z:
        shipped = sorted(Path(n).name for n in z.namelist() if n.endswith(".ipynb") and "demo" not in n)
    assert shipped == ["01_shape_matching.ipynb", "02_sign_correction.ipynb"]

    submitted, out = tmp_path / "submitted", tmp_path / "out"
    for sid, folder in (("teaching", paths.source), ("blank", paths.release)):
        (submitted / sid / "deformation").mkdir(parents=True)
        for stage in ("01_shape_matching", "02_sign_correction"):
            nb = nbformat.read(folder / "deformation" / f"{stage}.ipynb", as_version=4)
            nbformat.write(nb, submitted / sid / "deformation" / f"{stage}.ipynb")
    db = f"sqlite:///{tmp_path}/gradebook.db"
    results = grade_class(submitted, out, GradeOptions(db_url=db, progress=False, autograded=tmp_path / "autograded"), paths)
    rows = list(csv.DictReader((out / "grades.csv").open()))
    assert sorted({r["notebook"] for r in rows}) == ["01_shape_matching", "02_sign_correction"]
    scores = {(r["student_id"], r["notebook"]): r for r in results}
    for stage in ("01_shape_matching", "02_sign_correction"):
        teaching = scores["teaching", stage]
        assert teaching["score"] == teaching["max_score"] == report.points[stage]
        assert scores["blank", stage]["score"] == 0
    assert main(["report", str(out)]) == 0
    page = (out / "report" / "index.html").read_text()
    assert "01_shape_matching" in page and "03_arap" not in page
    assert main(["export", str(out), "--to", "moodle", "--file", str(tmp_path / "moodle.csv"), "--db", db]) == 0
    assert len(list(csv.reader((tmp_path / "moodle.csv").open()))) == 1 + 2
