"""Late policy: nbgrader's timestamp.txt against the due date, penalties with nbgrader's plugin semantics."""

import csv
import shutil
from datetime import datetime

import pytest

from grader.late_policy import (PerDayPenalty, apply_late_policy, configured_plugin, gradebook_due, make_plugin, parse_due,
                                read_timestamp)

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
