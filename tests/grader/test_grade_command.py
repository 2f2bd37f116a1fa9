"""`deformlab grade` on a small real class: every row written, whatever the students did."""

import csv
import json

import nbformat
import pytest

from grader.cli import main
from tests.corpus import student_notebook

NOTEBOOK = "01_shape_matching"


def as_student(source_nb):
    """The source notebook as a student who solved it would submit it."""
    return student_notebook(nbformat.read(source_nb, as_version=4), {})


@pytest.fixture(scope="module")
def graded(tmp_path_factory, source_notebooks):
    tmp = tmp_path_factory.mktemp("class")
    submitted = tmp / "submitted"
    good = submitted / "Ada_Lovelace" / "deformation"
    good.mkdir(parents=True)
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), good / f"{NOTEBOOK}.ipynb")
    garbage = submitted / "bob" / "deformation"
    garbage.mkdir(parents=True)
    (garbage / f"{NOTEBOOK}.ipynb").write_bytes(b"\x00\x01 not a notebook")
    renamed = submitted / "carol" / "deformation"
    renamed.mkdir(parents=True)
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), renamed / f"{NOTEBOOK} (1).ipynb")
    out = tmp / "out"
    argv = [str(submitted), "--out", str(out), "--workers", "2", "--timeout", "20", "--db", f"sqlite:///{tmp}/gb.db", "--seed", "7"]
    code = main(["grade", *argv])
    return tmp, out, code, argv


def rows(out):
    with open(out / "grades.csv") as fh:
        return list(csv.DictReader(fh))


def test_exit_status_is_zero_and_every_student_has_a_row_per_notebook(graded, source_notebooks):
    _, out, code, _ = graded
    assert code == 0
    table = rows(out)
    assert list(table[0]) == ["student_id", "assignment", "notebook", "score", "max_score", "bonus"]
    bonus = {"06_fast", "07_tetrahedra"}
    assert {r["bonus"] for r in table if r["notebook"] in bonus} <= {"true"}
    assert {r["bonus"] for r in table if r["notebook"] not in bonus} == {"false"}
    assert {(r["student_id"], r["notebook"]) for r in table} == {
        (s, n) for s in ("Ada_Lovelace", "bob", "carol") for n in source_notebooks
    }


def test_a_correct_notebook_earns_full_marks_and_others_missing_score_zero(graded):
    _, out, _, _ = graded
    table = {(r["student_id"], r["notebook"]): r for r in rows(out)}
    ada = table[("Ada_Lovelace", NOTEBOOK)]
    assert float(ada["score"]) == float(ada["max_score"]) > 0
    assert float(table[("Ada_Lovelace", "03_arap")]["score"]) == 0
    assert float(table[("bob", NOTEBOOK)]["score"]) == 0


def test_the_log_says_why_each_row_scored_what_it_did(graded):
    _, out, _, _ = graded
    log = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    by = {(r["student_id"], r["notebook"]): r for r in log}
    assert by[("bob", NOTEBOOK)]["status"] == "invalid" and "not a Jupyter notebook" in by[("bob", NOTEBOOK)]["reasons"][0]
    assert by[("Ada_Lovelace", "03_arap")]["status"] == "missing"
    assert "renamed" in " ".join(by[("carol", NOTEBOOK)]["notes"])
    assert by[("Ada_Lovelace", NOTEBOOK)]["seed"] == 7
    assert by[("Ada_Lovelace", NOTEBOOK)]["peak_rss_bytes"] > 0


def test_feedback_pages_show_each_function(graded):
    _, out, _, _ = graded
    page = (out / "feedback" / "Ada_Lovelace" / f"{NOTEBOOK}.html").read_text()
    for fn in ("centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align"):
        assert f"<code>{fn}</code>" in page


def test_the_gradebook_holds_the_autograded_scores(graded):
    from nbgrader.api import Gradebook

    tmp, _, _, _ = graded
    with Gradebook(f"sqlite:///{tmp}/gb.db") as gb:
        nb = gb.find_submission_notebook(NOTEBOOK, "deformation", "Ada_Lovelace")
        assert nb.score == pytest.approx(sum(g.max_score for g in nb.grades if g.cell.cell_type == "code"))
        assert {s.id for s in gb.students} >= {"Ada_Lovelace", "bob", "carol"}


def test_rerunning_into_the_same_folder_reuses_results_and_writes_the_same_grades(graded):
    _, out, _, argv = graded
    before = (out / "grades.csv").read_text()
    assert main(["grade", *argv]) == 0
    assert (out / "grades.csv").read_text() == before
    log = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    assert log[-1]["reused"] is True
    keys = [(r["student_id"], r["notebook"]) for r in log]
    assert len(keys) == len(set(keys)) == len(rows(out)), "one log record per student × notebook"


def test_grade_prints_a_score_table_per_student_and_per_notebook(graded, capsys):
    _, _, _, argv = graded
    assert main(["grade", *argv]) == 0
    printed = capsys.readouterr().out
    table = printed[printed.index("student "):]
    ada = next(line.split() for line in table.splitlines() if line.startswith("Ada_Lovelace"))
    full = {r["notebook"]: r["max_score"] for r in rows(graded[1]) if r["student_id"] == "Ada_Lovelace"}
    assert ada[2] == f"{float(full[NOTEBOOK]):g}/{float(full[NOTEBOOK]):g}", "01 is the second column"
    assert "median" in table and any(line.startswith(NOTEBOOK) for line in table.splitlines())


def test_one_student_is_graded_again_without_touching_the_others(graded, source_notebooks):
    tmp, out, _, argv = graded
    ada = out / "units" / "Ada_Lovelace" / f"{NOTEBOOK}.json"
    ada_before = ada.read_bytes(), ada.stat().st_mtime_ns
    bob = tmp / "submitted" / "bob" / "deformation" / f"{NOTEBOOK}.ipynb"
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), bob)  # bob resubmits a correct notebook
    try:
        assert main(["grade", *argv, "--student", "bob"]) == 0
    finally:
        bob.write_bytes(b"\x00\x01 not a notebook")
    table = {(r["student_id"], r["notebook"]): r for r in rows(out)}
    assert float(table[("bob", NOTEBOOK)]["score"]) == float(table[("bob", NOTEBOOK)]["max_score"]) > 0
    assert (ada.read_bytes(), ada.stat().st_mtime_ns) == ada_before
    log = [json.loads(line) for line in (out / "log.jsonl").read_text().splitlines()]
    assert {r["student_id"] for r in log if not r["reused"]} == {"bob"}
    assert main(["grade", *argv]) == 0  # and back: the original bob is graded again on the plain re-run


def test_regrading_one_late_student_leaves_every_other_students_late_penalty_as_it_was(graded):
    tmp, out, _, argv = graded
    stamps = {sid: tmp / "submitted" / sid / "deformation" / "timestamp.txt" for sid in ("Ada_Lovelace", "carol")}
    for path in stamps.values():
        path.write_text("2026-11-22 10:00:00.000000 UTC")  # both late; the first run had no due date
    try:
        assert main(["grade", *argv, "--student", "carol", "--due", "2026-11-20 23:59:00 UTC", "--late-policy", "zero"]) == 0
    finally:
        for path in stamps.values():
            path.unlink()
    table = {(r["student_id"], r["notebook"]): r for r in rows(out)}
    carol, ada = table[("carol", NOTEBOOK)], table[("Ada_Lovelace", NOTEBOOK)]
    assert float(carol["late_penalty"]) == float(carol["score"]) > 0
    assert (ada["seconds_late"], ada["late_penalty"]) == ("0", "0"), "Ada was not regraded: her row stays as it was"
    assert "Late:" not in (out / "feedback" / "Ada_Lovelace" / f"{NOTEBOOK}.html").read_text()


def test_an_unknown_student_is_a_usage_error(graded, capsys):
    _, _, _, argv = graded
    assert main(["grade", *argv, "--student", "nobody"]) == 2
    assert "'nobody': no such student" in capsys.readouterr().err


def test_a_missing_submitted_folder_is_a_usage_error(tmp_path, capsys):
    assert main(["grade", str(tmp_path / "nope"), "--out", str(tmp_path / "o")]) == 2
    assert "not a folder" in capsys.readouterr().err


@pytest.mark.parametrize("bad", ["0", "-4", "lots", "2.5"])
def test_a_process_cap_that_is_not_a_positive_integer_is_a_usage_error(tmp_path, capsys, bad):
    with pytest.raises(SystemExit) as stop:
        main(["grade", str(tmp_path), "--out", str(tmp_path / "o"), "--max-processes", bad])
    assert stop.value.code == 2
    assert f"--max-processes: must be a positive integer, got {bad!r}" in capsys.readouterr().err


def test_a_syntax_error_is_named_where_the_student_wrote_it_not_as_a_name_error(tmp_path, source_notebooks):
    submitted = tmp_path / "submitted" / "sam" / "deformation"
    submitted.mkdir(parents=True)
    broken = "import numpy as np\n\n\ndef centroid(P, w=None):\n    P = np.asarray(P, float\n    return P.mean(axis=0)\n"
    nbformat.write(student_notebook(nbformat.read(source_notebooks[NOTEBOOK], as_version=4), {"centroid": broken}),
                   submitted / f"{NOTEBOOK}.ipynb")
    out = tmp_path / "out"
    assert main(["grade", str(tmp_path / "submitted"), "--out", str(out), "--workers", "1", "--db", f"sqlite:///{tmp_path}/gb.db"]) == 0
    unit = json.loads((out / "units" / "sam" / f"{NOTEBOOK}.json").read_text())
    centroid = next(t for t in unit["tests"] if t["function"] == "centroid")
    assert centroid["score"] == 0
    assert centroid["summary"] == ("centroid was never defined: the cell defining centroid() failed with "
                                   "SyntaxError: '(' was never closed (line 5 of the cell)")
    assert unit["reasons"] == ["the cell defining centroid(): SyntaxError: '(' was never closed (line 5 of the cell)"]
    page = (out / "feedback" / "sam" / f"{NOTEBOOK}.html").read_text()
    assert "ipykernel" not in page and ".py, line" not in page and "NameError: centroid" not in page


def test_a_missing_notebook_names_the_files_no_notebook_claimed_and_a_linked_folder_says_so(tmp_path, source_notebooks):
    """A notebook saved under another name without its metadata, or a student folder that is a link: the TA reads why.

    Every student's file name a note shows is made printable first, a renamed notebook's too.
    """
    submitted = tmp_path / "submitted"
    dave = submitted / "dave" / "deformation"
    dave.mkdir(parents=True)
    nbformat.write(nbformat.v4.new_notebook(), dave / "scratch.ipynb")  # pasted into a fresh notebook: no metadata
    (dave / "bad\nname.ipynb").write_bytes(b"{}")
    elsewhere = tmp_path / "elsewhere" / "deformation"
    elsewhere.mkdir(parents=True)
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), elsewhere / f"{NOTEBOOK}.ipynb")
    (submitted / "erin").symlink_to(elsewhere.parent, target_is_directory=True)
    frank = submitted / "frank" / "deformation"
    frank.mkdir(parents=True)
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), frank / "x\x1b[2Jy.ipynb")  # renamed; a terminal escape in its name
    out = tmp_path / "out"
    assert main(["grade", str(submitted), "--out", str(out), "--workers", "1", "--timeout", "20",
                 "--db", f"sqlite:///{tmp_path}/gb.db"]) == 0
    log = {(r["student_id"], r["notebook"]): r for r in map(json.loads, (out / "log.jsonl").read_text().splitlines())}
    for notebook in source_notebooks:
        dave_row, erin_row = log[("dave", notebook)], log[("erin", notebook)]
        assert dave_row["status"] == erin_row["status"] == "missing"
        (note,) = dave_row["notes"]
        assert "'scratch.ipynb'" in note and "'bad?name.ipynb'" in note and "no notebook of this assignment claims" in note
        assert erin_row["notes"] == ["the submission folder is a link, which is not followed"]
    assert log[("frank", NOTEBOOK)]["notes"] == [f"graded 'x?[2Jy.ipynb' as {NOTEBOOK}.ipynb (renamed file)"]
    page = (out / "feedback" / "dave" / f"{NOTEBOOK}.html").read_text()
    assert "scratch.ipynb" in page and "bad\nname" not in page
    assert {r["student_id"] for r in rows(out)} == {"dave", "erin", "frank"}


def test_an_assignment_folder_that_is_a_link_is_not_followed_even_to_a_notebook_of_the_right_name(tmp_path, source_notebooks):
    """A real student folder whose deformation/ links elsewhere (the instructor's notebooks, say): graded as nothing.

    Opening the notebook without following a link guards its last path component only; the folders above it are
    the plan's to refuse.
    """
    submitted = tmp_path / "submitted"
    (submitted / "gail").mkdir(parents=True)
    elsewhere = tmp_path / "elsewhere" / "deformation"
    elsewhere.mkdir(parents=True)
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), elsewhere / f"{NOTEBOOK}.ipynb")
    (submitted / "gail" / "deformation").symlink_to(elsewhere, target_is_directory=True)
    honest = submitted / "hal" / "deformation"
    honest.mkdir(parents=True)
    nbformat.write(as_student(source_notebooks[NOTEBOOK]), honest / f"{NOTEBOOK}.ipynb")
    out = tmp_path / "out"
    assert main(["grade", str(submitted), "--out", str(out), "--workers", "1", "--timeout", "20",
                 "--db", f"sqlite:///{tmp_path}/gb.db"]) == 0
    log = {(r["student_id"], r["notebook"]): r for r in map(json.loads, (out / "log.jsonl").read_text().splitlines())}
    for notebook in source_notebooks:
        assert log[("gail", notebook)]["status"] == "missing"
        assert log[("gail", notebook)]["notes"] == ["the submission folder is a link, which is not followed"]
    assert log[("hal", NOTEBOOK)]["status"] == "graded"
    assert {r["student_id"] for r in rows(out)} == {"gail", "hal"}
