"""The class report: built from the run's per-case verdicts, offline, escaped, with the same numbers as CSV."""

import csv
import re

from grader.cli import main
from grader.report.class_report import write_class_report

from .conftest import HOSTILE_ID


def read_csv(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def test_the_report_counts_what_grading_found(graded_class):
    _, _, out, results = graded_class
    page = write_class_report(out)
    notebooks = {r["notebook"]: r for r in read_csv(page.parent / "notebooks.csv")}
    assert notebooks["02_sign_correction"]["students"] == "6"
    assert notebooks["02_sign_correction"]["missing"] == "1" and notebooks["02_sign_correction"]["invalid"] == "1"
    full = sum(r["score"] == r["max_score"] for r in results if r["notebook"] == "01_shape_matching")
    assert int(notebooks["01_shape_matching"]["full_marks"]) == full == 4
    functions = {r["function"]: r for r in read_csv(page.parent / "functions.csv")}
    # ada full; bob and carl lose the reflection cases; blank, the unreadable file and the missing notebook score 0.
    assert (functions["optimal_rotation"]["full"], functions["optimal_rotation"]["partial"], functions["optimal_rotation"]["zero"]) == ("1", "2", "3")


def test_the_case_failed_most_names_its_students_and_hides_their_ids(graded_class):
    _, _, out, results = graded_class
    page = write_class_report(out)
    cases = read_csv(page.parent / "cases.csv")
    top = cases[0]
    assert top["function"] in ("optimal_rotation", "rigid_align")
    # bob and carl (the copy) fail the reflection cases; blank left every function as the stub, which is not a failure.
    assert int(top["students_failed"]) == 2
    for sid in ("bob", "carl", "blank"):
        assert not re.search(rf"\b{sid}\b", cases[0]["example_message"])


def test_the_page_opens_offline_and_shows_student_text_as_text(graded_class):
    _, _, out, _ = graded_class
    html = write_class_report(out).read_text()
    assert '<html lang="en">' in html
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", html), "nothing loaded from the network"
    assert "<script" not in html
    assert HOSTILE_ID not in html and "eve&lt;img src=x onerror=alert(1)&gt;" in html
    assert html.count("data:image/png;base64,") == 3


def test_deformlab_report_writes_the_page_and_says_where(graded_class, capsys, tmp_path):
    _, _, out, _ = graded_class
    assert main(["report", str(out), "--to", str(tmp_path / "r")]) == 0
    assert str(tmp_path / "r" / "index.html") in capsys.readouterr().out
    assert (tmp_path / "r" / "incidents.csv").is_file()


def test_report_of_a_folder_that_was_not_graded_is_a_usage_error(tmp_path, capsys):
    assert main(["report", str(tmp_path)]) == 2
    assert "has no grades.csv" in capsys.readouterr().err


def test_unattempted_functions_do_not_fill_the_hidden_cases_failed_most(graded_class):
    _, _, out, results = graded_class
    blank = [c for r in results if r["student_id"] == "blank" for t in r["tests"] for c in t["cases"]]
    assert blank and all(c["error"].startswith("NotImplementedError") for c in blank)
    cases = read_csv(write_class_report(out).parent / "cases.csv")
    assert cases and not any("NotImplementedError" in c["example_message"] for c in cases)
    # Only bob's and carl's reflection failures are left, on the functions they got wrong.
    assert {c["function"] for c in cases} <= {"optimal_rotation", "rigid_align"}
