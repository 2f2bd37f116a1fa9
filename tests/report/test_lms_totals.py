"""The one number per student that LMS exports carry: regular + bonus, minus late penalties, maximum without bonus."""

import pytest

from grader.exports.lms import moodle_csv, totals


def test_bonus_counts_as_extra_credit_and_late_penalties_are_subtracted(tmp_path):
    grades = tmp_path / "grades.csv"
    grades.write_text(
        "student_id,assignment,notebook,score,max_score,bonus,seconds_late,late_penalty\n"
        "ada,deformation,05_lbs,10,12,false,0,0\n"
        "ada,deformation,06_fast,5,15,true,0,0\n"
        "bob,deformation,05_lbs,12,12,false,90000,3\n"
        "bob,deformation,06_fast,0,15,true,90000,0\n"
    )
    rows = {t.student_id: t for t in totals(grades)}
    assert (rows["ada"].score, rows["ada"].max_score) == (15, 12)
    assert (rows["bob"].score, rows["bob"].max_score) == (9, 12)
    assert moodle_csv(list(rows.values()), "Lab").splitlines() == ["ID number,Lab", "ada,15", "bob,9"]


def test_grades_without_late_columns_are_read_as_on_time(tmp_path):
    grades = tmp_path / "grades.csv"
    grades.write_text("student_id,assignment,notebook,score,max_score,bonus\nada,deformation,05_lbs,10,12,false\n")
    assert totals(grades)[0].score == pytest.approx(10)


def test_late_days_and_penalties_reach_moodles_feedback_column(tmp_path):
    from grader.cli import main

    out = tmp_path / "out"
    out.mkdir()
    (out / "grades.csv").write_text(
        "student_id,assignment,notebook,score,max_score,bonus,seconds_late,late_days,late_penalty\n"
        "ada,deformation,05_lbs,10,12,false,0,0,0\n"
        "bob,deformation,05_lbs,12,12,false,126000,1,3\n"
        "bob,deformation,06_fast,4,15,true,126000,1,0\n"
    )
    assert main(["export", str(out), "--to", "moodle", "--column", "Lab"]) == 0
    assert (out / "moodle.csv").read_text().splitlines() == [
        "ID number,Lab,Feedback", "ada,10,", "bob,13,submitted 35.0 h late; 1 late day spent; late penalty 3 points"]
