"""Submissions built to break the reader or to forge grading metadata become a graded or invalid row, never a crash."""

from __future__ import annotations

import json

import nbformat
import pytest

from tests.corpus import student_notebook
from grader.pipeline.sanitize import sanitize
from grader.pipeline.read_submission import SubmissionError, read_submission

NOTEBOOK = "01_shape_matching"


@pytest.fixture(scope="module")
def source(source_notebooks):
    return nbformat.read(source_notebooks[NOTEBOOK], as_version=4)


def _graded_meta(nb):
    return {c.metadata["nbgrader"]["grade_id"]: c.metadata["nbgrader"] for c in nb.cells if "nbgrader" in c.metadata}


def test_forged_points_locks_and_graded_cells_are_replaced_by_the_source_metadata(source):
    nb = student_notebook(source, {})
    for cell in nb.cells:
        if "nbgrader" in cell.metadata:
            cell.metadata["nbgrader"].update(points=1000, locked=False)
            cell.metadata["extra"] = {"nested": list(range(5))}
    nb.cells.append(nbformat.v4.new_code_cell("x = 1", metadata={"nbgrader": {"grade": True, "grade_id": "test_forged", "points": 1000}}))
    repaired = sanitize(nb, source).nb
    assert _graded_meta(repaired) == _graded_meta(source)
    assert all("extra" not in c.metadata for c in repaired.cells)
    assert repaired.cells[-1].source == "x = 1" and repaired.cells[-1].metadata == {}


def test_metadata_that_is_not_a_dict_is_ignored(source):
    nb = student_notebook(source, {})
    nb.cells[0].metadata["nbgrader"] = ["not", "a", "dict"]
    sanitize(nb, source)


def test_a_lone_surrogate_is_replaced_so_the_notebook_can_be_written(source, tmp_path):
    nb = student_notebook(source, {})
    nb.cells.append(nbformat.v4.new_markdown_cell("placeholder"))
    raw = json.loads(nbformat.writes(nb))
    raw["cells"][-1]["source"] = "caf\ud800 au lait"
    (tmp_path / "s.ipynb").write_bytes(json.dumps(raw).encode())
    repaired = sanitize(read_submission(tmp_path / "s.ipynb"), source).nb
    assert repaired.cells[-1].source == "caf\ufffd au lait"
    nbformat.writes(repaired).encode("utf-8")


def test_json_nested_past_the_recursion_limit_is_an_invalid_submission(tmp_path):
    (tmp_path / "deep.ipynb").write_bytes(b'{"cells": [], "metadata": ' + b"[" * 100_000 + b"]" * 100_000 + b"}")
    with pytest.raises(SubmissionError, match="nested too deeply"):
        read_submission(tmp_path / "deep.ipynb")


def test_a_submission_that_is_a_link_is_not_followed(source, tmp_path):
    target = tmp_path / "elsewhere.ipynb"
    nbformat.write(student_notebook(source, {}), target)
    (tmp_path / "s.ipynb").symlink_to(target)
    with pytest.raises(SubmissionError, match="link"):
        read_submission(tmp_path / "s.ipynb")


def test_a_fifo_submission_is_refused_without_blocking(tmp_path):
    import os

    os.mkfifo(tmp_path / "s.ipynb")
    with pytest.raises(SubmissionError, match="not a regular file"):
        read_submission(tmp_path / "s.ipynb")
