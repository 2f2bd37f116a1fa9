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


@pytest.fixture
def hand_graded(graded_class, tmp_path):
    """A copy of the run's gradebook after a TA's session in formgrader: ada's written answers graded (one with a
    comment holding markup), bob's first autograded cell changed and given extra credit; carl's answers left."""
    import shutil

    from nbgrader.api import Gradebook

    paths, _, out, _ = graded_class
    db = f"sqlite:///{tmp_path}/gb.db"
    shutil.copy(paths.root / "gb.db", tmp_path / "gb.db")
    given = {}
    with Gradebook(db) as gb:
        for nb in gb.find_submission("deformation", "ada").notebooks:
            for grade in nb.grades:
                if grade.cell.cell_type == "markdown":  # as formgrader's API handler saves a score
                    grade.manual_score = grade.max_score / 2
                    grade.needs_manual_grade = False
                    given[(nb.name, grade.name)] = grade.max_score / 2
        comment = next(c for nb in gb.find_submission("deformation", "ada").notebooks for c in nb.comments
                       if (nb.name, c.name) == next(iter(given)))
        comment.manual_comment = "Good, but <b>why</b> the candy wrapper?"
        bob = gb.find_submission_notebook("01_shape_matching", "deformation", "bob")
        test = next(g for g in bob.grades if g.cell.cell_type == "code")
        test.manual_score, test.extra_credit = test.max_score, 1.5
        gb.db.commit()
        scores = {s.student.id: (s.score, s.max_score) for s in gb.find_assignment("deformation").submissions}
    assert given and len(given) == 2, "01 and 02 each have a written answer"
    return out, db, given, scores


def test_exchange_files_behind_a_linked_submission_folder_are_not_copied(tmp_path):
    """Through a linked student or assignment folder, another student's submission_secret.txt would be released as theirs."""
    from grader.exports.nbgrader_feedback import export_feedback

    other = tmp_path / "submitted" / "ada" / "deformation"
    other.mkdir(parents=True)
    for name in ("timestamp.txt", "submission_secret.txt"):
        (other / name).write_text("ada's")
    (tmp_path / "submitted" / "eve").mkdir()
    (tmp_path / "submitted" / "eve" / "deformation").symlink_to(other, target_is_directory=True)
    (tmp_path / "submitted" / "fay").symlink_to(other.parent, target_is_directory=True)
    for sid in ("ada", "eve", "fay"):
        (tmp_path / "out" / "feedback" / sid).mkdir(parents=True)
        (tmp_path / "out" / "feedback" / sid / "00_meshes.html").write_text("<p>page</p>")
    _, unreleasable = export_feedback(tmp_path / "out", tmp_path / "submitted", tmp_path / "feedback", "deformation")
    assert unreleasable == ["eve", "fay"]
    assert (tmp_path / "feedback" / "ada" / "deformation" / "submission_secret.txt").read_text() == "ada's"
    for sid in ("eve", "fay"):
        assert (tmp_path / "feedback" / sid / "deformation" / "00_meshes.html").is_file()
        assert not (tmp_path / "feedback" / sid / "deformation" / "submission_secret.txt").exists()


def test_lms_totals_are_the_gradebooks_with_every_point_graded_by_hand(hand_graded, tmp_path, capsys):
    out, db, given, scores = hand_graded
    target = tmp_path / "canvas.csv"
    assert main(["export", str(out), "--to", "canvas", "--file", str(target), "--db", db]) == 0
    rows = read(target)
    totals = {r[3]: float(r[5]) for r in rows[2:]}
    assert float(rows[1][5]) == pytest.approx(scores["ada"][1]), "Points Possible counts the written answers"
    autograded = expected_totals(out)
    assert totals["ada"] == pytest.approx(autograded["ada"] + sum(given.values())) == pytest.approx(scores["ada"][0])
    assert totals["bob"] == pytest.approx(scores["bob"][0]) and totals["bob"] > autograded["bob"] + 1.5 - 1e-9
    assert totals["carl"] == pytest.approx(autograded["carl"])
    assert "written answer(s) are not graded by hand yet" in capsys.readouterr().err
    moodle = tmp_path / "moodle.csv"
    assert main(["export", str(out), "--to", "moodle", "--file", str(moodle), "--db", db]) == 0
    notes = {r[0]: r[2] for r in read(moodle)[1:]}
    assert notes["ada"] == f"{sum(given.values()):g} points graded by hand"
    assert notes["carl"] == "2 written answers not graded yet"


def test_exported_feedback_shows_the_hand_grading_and_a_re_export_picks_up_more(hand_graded, graded_class, tmp_path):
    from nbgrader.api import Gradebook

    out, db, given, _ = hand_graded
    _, submitted, _, _ = graded_class
    dest = tmp_path / "feedback"
    argv = ["export", str(out), "--to", "nbgrader-feedback", "--submitted", str(submitted), "--file", str(dest), "--db", db]
    assert main(argv) == 0
    (notebook, cell), points = next(iter(given.items()))
    page = (dest / "ada" / "deformation" / f"{notebook}.html").read_text()
    assert f"<li class=\"manual\">{cell}: {points:g} / {2 * points:g}. TA&#x27;s comment: Good, but &lt;b&gt;why&lt;/b&gt; the candy wrapper?</li>" in page
    assert "your written answers are read by a TA" not in page and "<b>why</b>" not in page
    bob = (dest / "bob" / "deformation" / "01_shape_matching.html").read_text()
    assert "set by a TA (autograded: " in bob and "extra credit +1.5" in bob
    carl = (dest / "carl" / "deformation" / "01_shape_matching.html").read_text()
    assert "not graded yet" in carl
    with Gradebook(db) as gb:  # the TA grades carl's answer; the next export shows it
        for grade in gb.find_submission_notebook("01_shape_matching", "deformation", "carl").grades:
            if grade.cell.cell_type == "markdown":
                grade.manual_score, grade.needs_manual_grade = grade.max_score, False
        gb.db.commit()
    assert main(argv) == 0
    carl = (dest / "carl" / "deformation" / "01_shape_matching.html").read_text()
    assert "not graded yet" not in carl and carl.count("<!-- manual -->") == 1


def test_a_missing_notebooks_feedback_promises_no_reading_of_its_written_answers(graded_class):
    _, _, out, _ = graded_class
    page = (out / "feedback" / "dan" / "02_sign_correction.html").read_text()
    assert "there is nothing to grade by hand" in page and "read by a TA" not in page
    assert "read by a TA" in (out / "feedback" / "dan" / "01_shape_matching.html").read_text()


def test_a_page_graded_before_the_manual_marks_still_gets_the_hand_grading():
    from grader.exports.gradebook import HandGrade
    from grader.exports.nbgrader_feedback import with_hand_grades

    old = ('<p class="score">Autograded score: <b>3.00 / 5</b></p>\n<!-- late -->\n'
           '<p class="manual">2 more points of this notebook are graded by hand (answer_nut): your written answers are read by a TA.</p>\n'
           '<p>The hidden tests ran your functions on inputs drawn with seed 5.</p>')
    page = with_hand_grades(old, [HandGrade("00_meshes", "answer_nut", True, 1.5, 2.0)])
    assert "read by a TA" not in page and page.count("<!-- manual -->") == 1
    assert '<li class="manual">answer_nut: 1.5 / 2</li>' in page and page.index("answer_nut: 1.5") < page.index("The hidden tests ran")
    bare = with_hand_grades(old.replace(old.split("\n")[2] + "\n", ""), [HandGrade("00_meshes", "answer_nut", True, None, 2.0)])
    assert "answer_nut: not graded yet" in bare and bare.index("not graded yet") < bare.index("The hidden tests ran")


def test_a_gradebook_that_holds_a_student_otherwise_than_the_run_is_not_used_for_that_student(hand_graded, tmp_path, capsys):
    from nbgrader.api import Gradebook

    out, db, given, _ = hand_graded
    with Gradebook(db) as gb:  # as if ada had been graded again into this gradebook by another run
        grade = next(g for g in gb.find_submission_notebook("01_shape_matching", "deformation", "ada").grades if g.cell.cell_type == "code")
        grade.auto_score = 0.0
        gb.db.commit()
    target = tmp_path / "moodle.csv"
    assert main(["export", str(out), "--to", "moodle", "--file", str(target), "--db", db]) == 0
    assert "holds other notebooks or autograded points than" in capsys.readouterr().err
    totals = {r[0]: float(r[1]) for r in read(target)[1:]}
    assert totals["ada"] == pytest.approx(expected_totals(out)["ada"]), "grades.csv's, without the gradebook's hand grading"
