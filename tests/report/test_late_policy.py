"""Late policy: nbgrader's timestamp.txt against the due date, penalties with nbgrader's plugin semantics."""

import csv
import shutil
from datetime import datetime

from nbgrader.api import Gradebook

import pytest

from grader.late_policy import (PerDayPenalty, apply_late_policy, configured_late_days, configured_plugin, gradebook_due,
                                keep_late_columns, make_plugin, parse_due, previous_late_columns, read_timestamp)

DUE = "2026-11-20 23:59:00 UTC"


def test_per_day_penalty_counts_started_days_after_the_grace_period():
    plugin = PerDayPenalty(fraction_per_day=0.1, grace_seconds=600)
    assert plugin.late_submission_penalty("ada", 10.0, 300) is None
    assert plugin.late_submission_penalty("ada", 10.0, 601) == pytest.approx(1.0)
    assert plugin.late_submission_penalty("ada", 10.0, 600 + 86400 + 1) == pytest.approx(2.0)
    assert plugin.late_submission_penalty("ada", 10.0, 600 + 30 * 86400) == pytest.approx(10.0)


def test_nbgraders_own_plugin_gives_zero_or_nothing():
    assert make_plugin("zero").late_submission_penalty("ada", 7.0, 10) == 7.0
    assert make_plugin("none").late_submission_penalty("ada", 7.0, 10) is None
    assert isinstance(make_plugin("grader.late_policy:PerDayPenalty"), PerDayPenalty)


@pytest.mark.parametrize("spec", ["per-day:2", "per-day:x", "os:path", "nope:Nope", "half"])
def test_a_policy_that_names_no_plugin_is_refused(spec):
    with pytest.raises(ValueError, match="late policy"):
        make_plugin(spec)


def test_the_plugin_and_its_settings_come_from_nbgrader_config_as_autograde_reads_them(tmp_path):
    config = tmp_path / "nbgrader_config.py"
    config.write_text("c = get_config()\n"
                      "c.AssignLatePenalties.plugin_class = 'grader.late_policy.PerDayPenalty'\n"
                      "c.PerDayPenalty.fraction_per_day = 0.25\n")
    plugin = configured_plugin(config)
    assert isinstance(plugin, PerDayPenalty) and plugin.late_submission_penalty("ada", 8.0, 90000) == pytest.approx(4.0)
    config.write_text("c = get_config()\nc.LateSubmissionPlugin.penalty_method = 'zero'\n")
    assert configured_plugin(config).late_submission_penalty("ada", 8.0, 10) == 8.0
    assert configured_plugin(tmp_path / "none.py").late_submission_penalty("ada", 8.0, 10) is None


def test_the_due_date_is_the_gradebooks_own(tmp_path):
    from nbgrader.api import Gradebook

    db = f"sqlite:///{tmp_path}/gb.db"
    with Gradebook(db) as gb:
        gb.add_assignment("deformation", duedate=datetime(2026, 11, 20, 22, 59))
        gb.add_assignment("other")
    assert gradebook_due(db, "deformation") == datetime(2026, 11, 20, 22, 59)
    assert gradebook_due(db, "other") is None and gradebook_due(db, "missing") is None


def test_due_dates_are_read_as_nbgrader_reads_them():
    assert parse_due("2026-11-20 23:59:00 Europe/Paris") == datetime(2026, 11, 20, 22, 59)
    with pytest.raises(ValueError, match="is not a date"):
        parse_due("next friday-ish")


def test_a_hostile_timestamp_file_counts_as_on_time_and_says_why(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "timestamp.txt").write_text("2026-11-21 10:00:00.000000 UTC")
    assert read_timestamp(tmp_path / "a") == (datetime(2026, 11, 21, 10, 0), None)
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "timestamp.txt").symlink_to("/etc/hostname")
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "timestamp.txt").write_text("x" * 10_000)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "timestamp.txt").write_text("not a date")
    for name in "bcd":
        stamp, why = read_timestamp(tmp_path / name)
        assert stamp is None and "treated as on time" in why
    assert read_timestamp(tmp_path / "none") == (None, None)


def test_a_timestamp_behind_a_linked_folder_is_not_read(tmp_path):
    """A student or assignment folder that is a link leads elsewhere (another student's earlier timestamp.txt)."""
    other = tmp_path / "other" / "deformation"
    other.mkdir(parents=True)
    (other / "timestamp.txt").write_text("2026-11-01 10:00:00.000000 UTC")
    (tmp_path / "eve").mkdir()
    (tmp_path / "eve" / "deformation").symlink_to(other, target_is_directory=True)
    (tmp_path / "fay").symlink_to(other.parent, target_is_directory=True)
    assert read_timestamp(other) == (datetime(2026, 11, 1, 10, 0), None)
    for sid in ("eve", "fay"):
        stamp, why = read_timestamp(tmp_path / sid / "deformation")
        assert stamp is None and why == "the submission folder is a link, which is not followed; treated as on time"


def test_late_notebooks_lose_points_in_grades_csv_feedback_and_gradebook(graded_class, tmp_path):
    from nbgrader.api import Gradebook

    paths, submitted, out, _ = graded_class
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    db = tmp_path / "gb.db"
    shutil.copy(paths.root / "gb.db", db)
    stamps = {"ada": "2026-11-20 20:00:00.000000 UTC", "bob": "2026-11-22 11:00:00.000000 UTC"}  # bob: 35 h late
    for sid, text in stamps.items():
        (submitted / sid / "deformation" / "timestamp.txt").write_text(text)
    try:
        # First with a due date a day later (a TA's mistake), then the right one: the page shows only the last.
        apply_late_policy(copy, submitted, "deformation", parse_due("2026-11-21 23:59:00 UTC"), make_plugin("per-day:0.25"), None)
        late = apply_late_policy(copy, submitted, "deformation", parse_due(DUE), make_plugin("per-day:0.25"), f"sqlite:///{db}")
    finally:
        for sid in stamps:
            (submitted / sid / "deformation" / "timestamp.txt").unlink()
    with open(copy / "grades.csv", newline="") as fh:
        rows = {(r["student_id"], r["notebook"]): r for r in csv.DictReader(fh)}
    bob = rows[("bob", "01_shape_matching")]
    assert float(bob["seconds_late"]) == 35 * 3600 + 60
    assert float(bob["late_penalty"]) == pytest.approx(0.5 * float(bob["score"]))  # two started days × 0.25
    assert float(rows[("ada", "01_shape_matching")]["late_penalty"]) == 0
    assert set(late) == {"bob"}
    page = (copy / "feedback" / "bob" / "01_shape_matching.html").read_text()
    assert "submitted 1 d 11 h 1 min after the due date" in page and page.count('class="late"') == 1
    assert "Late:" not in (copy / "feedback" / "ada" / "01_shape_matching.html").read_text()
    with Gradebook(f"sqlite:///{db}") as gb:
        nb = gb.find_submission_notebook("01_shape_matching", "deformation", "bob")
        assert nb.late_submission_penalty == pytest.approx(float(bob["late_penalty"]))
        assert gb.find_submission("deformation", "bob").total_seconds_late == pytest.approx(35 * 3600 + 60)


def late_copy(graded_class, tmp_path):
    """A copy of the graded run and its gradebook, so a test's late policy leaves the shared run as it was."""
    paths, submitted, out, _ = graded_class
    copy = tmp_path / "out"
    shutil.copytree(out, copy)
    shutil.copy(paths.root / "gb.db", tmp_path / "gb.db")
    return submitted, copy, f"sqlite:///{tmp_path}/gb.db"


@pytest.fixture
def stamped(graded_class):
    """``stamp(sid, text)`` writes a student's timestamp.txt where nbgrader's collect does; removed afterwards."""
    _, submitted, _, _ = graded_class
    written = []

    def stamp(sid, text, folder=None):
        path = (folder or submitted / sid / "deformation") / "timestamp.txt"
        path.write_text(text)
        written.append(path)

    yield stamp
    for path in written:
        path.unlink()


def grades(out):
    with open(out / "grades.csv", newline="") as fh:
        return {(r["student_id"], r["notebook"]): r for r in csv.DictReader(fh)}


def test_an_extension_granted_by_the_command_moves_that_students_due_date_only(graded_class, stamped, tmp_path, capsys):
    from grader.cli import main

    submitted, out, db = late_copy(graded_class, tmp_path)
    stamped("bob", "2026-11-22 11:00:00.000000 UTC")  # 35 h 1 min late, within a two-day extension
    stamped("ada", "2026-11-21 01:00:00.000000 UTC")  # 1 h 1 min late, no extension
    with Gradebook(db) as gb:
        gb.find_assignment("deformation").duedate = parse_due(DUE)
        gb.db.commit()
    assert main(["extension", "bob", "--days", "2", "--db", db]) == 0
    assert "due for them 2026-11-22 23:59 UTC" in capsys.readouterr().out
    late = apply_late_policy(out, submitted, "deformation", parse_due(DUE), make_plugin("zero"), db)
    rows = grades(out)
    assert rows[("bob", "01_shape_matching")]["late_penalty"] == "0" and rows[("bob", "01_shape_matching")]["seconds_late"] == "0"
    assert float(rows[("ada", "01_shape_matching")]["late_penalty"]) == float(rows[("ada", "01_shape_matching")]["score"]) > 0
    assert late["bob"].extension.days == 2 and late["bob"].seconds_late == 0
    page = (out / "feedback" / "bob" / "01_shape_matching.html").read_text()
    assert "<b>Extension:</b> 2 d 0 h 0 min granted; submitted on time." in page
    with Gradebook(db) as gb:  # nbgrader's own reading of the same submission agrees
        assert gb.find_submission("deformation", "bob").total_seconds_late == 0
        assert gb.find_submission("deformation", "ada").total_seconds_late == 3660
    # Extensions replace each other, as nbgrader's grant_extension; --remove takes one back.
    assert main(["extension", "bob", "--remove", "--db", db]) == 0
    apply_late_policy(out, submitted, "deformation", parse_due(DUE), make_plugin("zero"), db)
    assert float(grades(out)[("bob", "01_shape_matching")]["seconds_late"]) == 35 * 3600 + 60


def test_an_extension_for_a_student_who_has_not_submitted_waits_in_the_gradebook(tmp_path, capsys):
    from grader.cli import main

    db = f"sqlite:///{tmp_path}/gb.db"
    with Gradebook(db) as gb:
        gb.add_assignment("deformation", duedate=parse_due(DUE))
    assert main(["extension", "zoe", "--until", "2026-11-23 12:00:00 UTC", "--db", db]) == 0
    with Gradebook(db) as gb:
        assert gb.find_submission("deformation", "zoe").duedate == datetime(2026, 11, 23, 12)
    for argv, message in ((["zoe", "--db", db], "needs --days, --hours or --until"),
                          (["zoe", "--until", "2026-11-19 12:00:00 UTC", "--db", db], "is not after the assignment's due date"),
                          (["zoe", "--days", "1", "--assignment", "other", "--db", db], "the gradebook has no assignment 'other'")):
        assert main(["extension", *argv]) == 2
        assert message in capsys.readouterr().err


def test_late_days_are_spent_whole_across_assignments_before_any_penalty(graded_class, stamped, tmp_path):
    submitted, out, db = late_copy(graded_class, tmp_path)
    with Gradebook(db) as gb:  # an earlier assignment: bob was 25 h late there, which spent 2 of his 3 days
        gb.add_assignment("warmup", duedate=datetime(2026, 11, 1, 12))
        gb.add_student("zed")
        gb.add_submission("warmup", "bob", timestamp=datetime(2026, 11, 2, 13))
        gb.add_submission("warmup", "zed", timestamp=datetime(2026, 11, 1, 11))
        gb.add_assignment("later", duedate=datetime(2026, 12, 1))  # due after: spends nothing before deformation
        gb.add_submission("later", "ada", timestamp=datetime(2026, 12, 9))
    stamped("bob", "2026-11-22 11:00:00.000000 UTC")  # 35 h 1 min late: needs 2 days, has 1
    stamped("ada", "2026-11-21 01:00:00.000000 UTC")  # 1 h 1 min late: needs 1 day, has 3
    late = apply_late_policy(out, submitted, "deformation", parse_due(DUE), make_plugin("per-day:0.25"), db, late_days=3)
    rows = grades(out)
    ada, bob = rows[("ada", "01_shape_matching")], rows[("bob", "01_shape_matching")]
    assert (ada["late_days"], ada["late_penalty"]) == ("1", "0")
    # One day covered, 11 h 1 min charged: one started day at 0.25.
    assert bob["late_days"] == "1" and float(bob["late_penalty"]) == pytest.approx(0.25 * float(bob["score"]))
    assert (late["bob"].late_days, late["bob"].late_days_left, late["ada"].late_days_left) == (1, 0, 2)
    page = (out / "feedback" / "bob" / "01_shape_matching.html").read_text()
    assert "1 late day spent on this assignment (0 left); late penalty" in page
    assert rows[("dan", "01_shape_matching")]["late_days"] == "0"
    from grader.report.class_report import write_class_report

    page = write_class_report(out)
    with open(page.parent / "late.csv", newline="") as fh:
        table = {r["student_id"]: r for r in csv.DictReader(fh)}
    assert set(table) == {"ada", "bob"} and (table["bob"]["late_days"], table["ada"]["late_days"]) == ("1", "1")
    assert float(table["bob"]["late_penalty"]) == pytest.approx(sum(float(r["late_penalty"]) for k, r in rows.items() if k[0] == "bob"), abs=1e-4)
    assert '<h2 id="late">Late work</h2>' in page.read_text()


def test_a_timestamp_one_folder_too_high_is_named_not_silently_ignored(graded_class, stamped, tmp_path, capsys):
    _, submitted, _, _ = graded_class
    submitted, out, _ = late_copy(graded_class, tmp_path)
    stamped("bob", "2026-11-25 10:00:00.000000 UTC", folder=submitted / "bob")
    late = apply_late_policy(out, submitted, "deformation", parse_due(DUE), make_plugin("zero"))
    assert "bob" not in late
    err = capsys.readouterr().err
    assert "'bob': timestamp.txt is one folder too high" in err and "counts as on time" in err


def test_the_late_day_budget_comes_from_nbgrader_config_as_the_plugin_does(tmp_path):
    config = tmp_path / "nbgrader_config.py"
    assert configured_late_days(config) == 0  # no file: no budget
    config.write_text("c = get_config()\nc.LateDays.budget = 3\n")
    assert configured_late_days(config) == 3
    config.write_text("c = get_config()\nc.LateDays.budget = -1\n")
    with pytest.raises(ValueError, match="a budget of late days cannot be negative"):
        configured_late_days(config)


def test_a_rewritten_grades_csv_gets_back_the_late_columns_of_the_run_before(tmp_path):
    grades = tmp_path / "grades.csv"
    grades.write_text("student_id,assignment,notebook,score,max_score,bonus,seconds_late,late_days,late_penalty\n"
                      "ada,deformation,05_lbs,10,12,false,90000,2,1.5\n")
    previous = previous_late_columns(tmp_path)
    grades.write_text("student_id,assignment,notebook,score,max_score,bonus\n"
                      "ada,deformation,05_lbs,10,12,false\nbob,deformation,05_lbs,12,12,false\n")
    keep_late_columns(tmp_path, previous)
    with open(grades, newline="") as fh:
        rows = {r["student_id"]: r for r in csv.DictReader(fh)}
    assert (rows["ada"]["seconds_late"], rows["ada"]["late_days"], rows["ada"]["late_penalty"]) == ("90000", "2", "1.5")
    assert (rows["bob"]["seconds_late"], rows["bob"]["late_penalty"]) == ("0", "0")
