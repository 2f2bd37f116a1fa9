"""What `deformlab release` prints is true: checks it skipped are not announced as passed, points match grades.csv."""

import contextlib
import io
from pathlib import Path

import nbformat
import pytest

from grader.build.release import ReleaseReport, check_grades, release
ASSIGNMENT = "deformation"
from grader.paths import CoursePaths

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def quick_release(tmp_path_factory):
    root = tmp_path_factory.mktemp("course")
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    (root / "assignments").mkdir()
    paths = CoursePaths(root)
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        report = release(paths=paths, execute=False)
    return paths, report, buf.getvalue()


def test_no_execute_does_not_claim_the_execution_checks_passed(quick_release):
    _, report, printed = quick_release
    assert report.ok and not report.executed
    assert "the reference earns every point, a blank submission earns none" not in printed
    assert "NOT checked (--no-execute)" in printed


def test_the_points_table_separates_autograded_from_hand_graded_points(quick_release):
    from grader.pipeline.verify import graded_cells

    paths, report, printed = quick_release
    for source in paths.source_notebooks(ASSIGNMENT):
        autograded = sum(c.points for c in graded_cells(nbformat.read(source, as_version=4)))
        assert report.points[source.stem] == autograded, "the autograded column is grades.csv's max_score"
        row = next(line.split() for line in printed.splitlines() if line.split()[:1] == [source.stem])
        assert float(row[1]) == autograded and float(row[2]) == report.manual_points[source.stem]
    assert sum(report.manual_points.values()) > 0, "the course has hand-graded answers"
    assert "graded by hand" in printed


def test_the_grading_check_names_no_scratch_folder(quick_release, capsys):
    paths, _, _ = quick_release
    report = ReleaseReport()
    sources = paths.source_notebooks(ASSIGNMENT)[:2]
    check_grades(sources, paths.release / ASSIGNMENT, False, report, "blank", paths)
    assert report.problems == []
    out = capsys.readouterr().out
    assert "dl-release-" not in out and "grades.csv" not in out


def test_a_notebook_loading_a_course_file_the_bundle_does_not_ship_is_refused_without_executing(tmp_path):
    """Every release, --no-execute too, checks that the data files the notebooks name are in the pack's bundle."""
    import dataclasses

    from grader.build.release import ReleaseReport, check_course_files
    from grader.course_pack import pack
    from grader.paths import CoursePaths

    course = pack("deformation")
    paths = CoursePaths(ROOT)
    report = ReleaseReport()
    check_course_files(paths, course, report)
    assert report.problems == []
    missing = dataclasses.replace(course, data=tuple(d for d in course.data if d != "bar_tet.npz"))
    check_course_files(paths, missing, report)
    assert report.problems == [
        f"07_tetrahedra.py loads data/bar_tet.npz, which the student bundle does not ship: "
        f"add it to data in {course.folder / 'assignment.toml'}"
    ]


@pytest.mark.parametrize("assignment", ["deformation", "smoothing"])
def test_a_notebook_naming_a_document_the_bundle_does_not_ship_is_refused_without_executing(assignment):
    """A notebook that tells students to read a document sends them nowhere unless the bundle has it."""
    import dataclasses

    from grader.build.release import ReleaseReport, check_named_documents
    from grader.course_pack import pack
    from grader.paths import CoursePaths

    course = pack(assignment)
    paths = CoursePaths(ROOT)
    report = ReleaseReport()
    check_named_documents(paths, course, report)
    assert report.problems == []
    if course.contract is not None:  # the smoothing notebook sends students to its contract
        check_named_documents(paths, dataclasses.replace(course, contract=None), report)
        assert report.problems == [
            f"00_laplacian_smoothing.py names CONTRACT.md, which the student bundle does not ship: add it to "
            f"[bundle] files in {course.folder / 'assignment.toml'}, or name a document the bundle has "
            f"(LIBRARY_POLICY.md, README.md)"
        ]
