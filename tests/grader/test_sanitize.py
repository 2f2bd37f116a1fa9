"""Submitted notebooks are repaired against the source before anything runs."""

import copy

import nbformat
import pytest

from grader.pipeline.sanitize import graded_functions, grading_plan, sanitize
from grader.pipeline.read_submission import SubmissionError, read_submission


@pytest.fixture(scope="module")
def source(source_notebooks):
    return nbformat.read(source_notebooks["02_sign_correction"], as_version=4)


def gid(cell):
    return (cell.metadata.get("nbgrader") or {}).get("grade_id")


def test_edited_tests_cells_are_restored_from_the_source(source):
    student = copy.deepcopy(source)
    tests = next(c for c in student.cells if gid(c) == "test_optimal_rotation")
    tests.source = "assert True"
    clean = sanitize(student, source)
    restored = next(c for c in clean.nb.cells if gid(c) == "test_optimal_rotation")
    assert restored.source == next(c for c in source.cells if gid(c) == "test_optimal_rotation").source
    assert any("restored the edited" in n for n in clean.notes)


def test_deleted_tests_cells_come_back_in_source_order(source):
    student = copy.deepcopy(source)
    student.cells = [c for c in student.cells if not (gid(c) or "").startswith("test_")]
    clean = sanitize(student, source)
    ids = [gid(c) for c in clean.nb.cells if gid(c)]
    assert [g for g in ids if g.startswith("test_")] == [gid(c) for c in source.cells if (gid(c) or "").startswith("test_")]
    assert ids.index("solution_optimal_rotation") < ids.index("test_optimal_rotation")


def test_duplicated_cells_and_ids_are_repaired(source):
    student = copy.deepcopy(source)
    dup_test = copy.deepcopy(next(c for c in student.cells if gid(c) == "test_rigid_align"))
    dup_solution = copy.deepcopy(next(c for c in student.cells if gid(c) == "solution_rigid_align"))
    student.cells += [dup_test, dup_solution]
    for c in student.cells:
        c["id"] = "same"
    clean = sanitize(student, source)
    assert sum(gid(c) == "test_rigid_align" for c in clean.nb.cells) == 1
    assert sum(gid(c) == "solution_rigid_align" for c in clean.nb.cells) == 1
    assert len({c["id"] for c in clean.nb.cells}) == len(clean.nb.cells)
    assert clean.nb.cells[-1].source == dup_solution.source, "a copied solution cell keeps the student's code"


def test_outputs_are_dropped(source):
    student = copy.deepcopy(source)
    code = next(c for c in student.cells if c.cell_type == "code")
    code.outputs = [nbformat.v4.new_output("stream", text="x" * 10_000_000)]
    clean = sanitize(student, source)
    assert all(not c.get("outputs") for c in clean.nb.cells if c.cell_type == "code")


def test_tests_cells_and_demonstrations_are_not_run_when_grading(source):
    nb = copy.deepcopy(source)
    nb.cells.append(nbformat.v4.new_code_cell("R = optimal_rotation(S)"))
    nb.cells.append(nbformat.v4.new_code_cell("def helper(S):\n    return optimal_rotation(S)"))
    plan = grading_plan(nb, graded_functions(nb))
    kinds = {i: (nb.cells[i].metadata.get("nbgrader") or {}) for i in plan}
    assert not any(m.get("grade") for m in kinds.values())
    assert len(nb.cells) - 2 not in plan, "a top-level call of a contract function is a demonstration"
    assert len(nb.cells) - 1 in plan, "a helper definition must run"
    assert all(i in plan for i, c in enumerate(nb.cells) if (c.metadata.get("nbgrader") or {}).get("solution") and c.cell_type == "code")


@pytest.mark.parametrize(
    "content, message",
    [
        (b"\x89PNG\r\n\x1a\n\x00garbage", "not a Jupyter notebook"),
        (b'{"cells": 3}', "no list of cells"),
        (b"[1, 2]", "no list of cells"),
    ],
)
def test_unreadable_files_are_rejected_with_a_reason(tmp_path, content, message):
    path = tmp_path / "03_arap.ipynb"
    path.write_bytes(content)
    with pytest.raises(SubmissionError, match=message):
        read_submission(path)


def test_a_notebook_of_another_assignment_is_rejected(source, tmp_path):
    other = nbformat.v4.new_notebook()
    other.cells.append(nbformat.v4.new_code_cell("x = 1", metadata={"nbgrader": {"grade_id": "q1", "grade": True, "points": 1}}))
    with pytest.raises(SubmissionError, match="shares no graded cell"):
        sanitize(other, source)


def test_a_missing_file_is_a_reason_not_a_crash(tmp_path):
    with pytest.raises(SubmissionError, match="cannot read"):
        read_submission(tmp_path / "absent.ipynb")


def released(source):
    """The student's copy as nbgrader's generate_assignment makes it: solutions and hidden tests cleared."""
    from nbgrader.preprocessors import ClearHiddenTests, ClearSolutions

    nb = copy.deepcopy(source)
    nb, _ = ClearSolutions().preprocess(nb, {})
    nb, _ = ClearHiddenTests().preprocess(nb, {})
    return nb


def test_an_untouched_release_notebook_gets_no_repair_note(source):
    clean = sanitize(released(source), source)
    assert clean.notes == []


def test_an_edited_release_tests_cell_is_still_reported(source):
    student = released(source)
    next(c for c in student.cells if gid(c) == "test_optimal_rotation").source += "\nassert True"
    clean = sanitize(student, source)
    assert clean.notes == ["restored the edited read-only cell test_optimal_rotation"]
