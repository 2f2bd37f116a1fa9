"""Exports: Canvas and Moodle gradebook files in their documented columns, and feedback nbgrader can release."""

import csv

import pytest

from grader.cli import main

from .conftest import HOSTILE_ID


def read(path):
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.reader(fh))


def expected_totals(out):
    totals = {}
    with open(out / "grades.csv", newline="") as fh:
        for row in csv.DictReader(fh):
            totals[row["student_id"]] = totals.get(row["student_id"], 0.0) + float(row["score"])
    return totals


def test_canvas_file_has_canvas_columns_points_possible_and_each_total(graded_class, tmp_path):
    _, _, out, results = graded_class
    target = tmp_path / "canvas.csv"
    assert main(["export", str(out), "--to", "canvas", "--column", "Deformation (4711)", "--file", str(target)]) == 0
    rows = read(target)
    # Canvas's import format: Student, ID, SIS User ID, SIS Login ID, Section, then one column per assignment.
    assert rows[0] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", "Deformation (4711)"]
    assert rows[1][0] == "Points Possible" and float(rows[1][5]) == sum(
        r["max_score"] for r in results if r["student_id"] == "ada")
    scores = {r[3]: float(r[5]) for r in rows[2:]}
    assert scores == pytest.approx(expected_totals(out))
    assert HOSTILE_ID in scores


def test_canvas_rows_carry_canvas_identity_from_its_roster_export(graded_class, tmp_path, capsys):
    _, _, out, _ = graded_class
    roster = tmp_path / "export.csv"
    roster.write_text(
        "Student,ID,SIS User ID,SIS Login ID,Section,Homework 1 (11),Current Score\n"
        "    Points Possible,,,,,10,\n"
        '"Lovelace, Ada",101,S-1,ada,Lab A,9,90\n'
        '"Babbage, Bob",102,S-2,bob,Lab B,7,70\n'
    )
    target = tmp_path / "canvas.csv"
    assert main(["export", str(out), "--to", "canvas", "--roster", str(roster), "--file", str(target)]) == 0
    rows = read(target)
    assert [r[:5] for r in rows[2:]] == [["Lovelace, Ada", "101", "S-1", "ada", "Lab A"], ["Babbage, Bob", "102", "S-2", "bob", "Lab B"]]
    assert "not in the roster" in capsys.readouterr().err


def test_a_roster_that_is_not_a_canvas_export_is_refused(graded_class, tmp_path, capsys):
    _, _, out, _ = graded_class
    roster = tmp_path / "names.csv"
    roster.write_text("name,email\nada,ada@example.org\n")
    assert main(["export", str(out), "--to", "canvas", "--roster", str(roster)]) == 2
    assert "not a Canvas gradebook export: missing column(s) Student, ID" in capsys.readouterr().err


def test_moodle_file_has_an_identifier_and_one_grade_item_column(graded_class, tmp_path):
    _, _, out, _ = graded_class
    target = tmp_path / "moodle.csv"
    assert main(["export", str(out), "--to", "moodle", "--column", "Deformation lab", "--file", str(target)]) == 0
    rows = read(target)
    assert rows[0] == ["ID number", "Deformation lab"]
    assert {r[0]: float(r[1]) for r in rows[1:]} == pytest.approx(expected_totals(out))


def test_nbgrader_release_feedback_returns_the_exported_pages(graded_class, tmp_path):
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from traitlets.config import Config

    _, submitted, out, _ = graded_class
    folder = submitted / "ada" / "deformation"
    (folder / "timestamp.txt").write_text("2026-11-20 10:00:00.000000 UTC")
    (folder / "submission_secret.txt").write_text("0123456789abcdef")
    (submitted / "bob" / "deformation" / "submission_secret.txt").symlink_to("/etc/hostname")
    course, exchange = tmp_path / "course", tmp_path / "exchange"
    try:
        assert main(["export", str(out), "--to", "nbgrader-feedback", "--submitted", str(submitted), "--file", str(course / "feedback")]) == 0
    finally:
        for f in ("timestamp.txt", "submission_secret.txt"):
            (folder / f).unlink()
        (submitted / "bob" / "deformation" / "submission_secret.txt").unlink()
    assert (course / "feedback" / "ada" / "deformation" / "02_sign_correction.html").is_file()
    assert not (course / "feedback" / "bob" / "deformation" / "submission_secret.txt").exists(), "a symlink is not followed"
    config = Config()
    config.CourseDirectory.root = str(course)
    config.CourseDirectory.course_id = "deformlab"
    config.Exchange.root = str(exchange)
    exchange.mkdir()
    api = NbGraderAPI(coursedir=CourseDirectory(config=config), config=config)
    result = api.release_feedback("deformation", "ada")
    assert result["success"], result.get("log")
    released = sorted((exchange / "deformlab" / "feedback").glob("*.html"))
    assert len(released) == 2
    assert {p.read_text() for p in released} == {
        (out / "feedback" / "ada" / f"{nb}.html").read_text() for nb in ("01_shape_matching", "02_sign_correction")}
