"""The grade ids of a built notebook's cells (nbgrader's ``grade_id``): written by the build, read everywhere else.

One place for the convention: a graded function ``f`` has its solution cell
``solution_f``, its autograded tests cell ``test_f`` and, in a stage that does not
grade it, its public check ``public_check_f``; written answers are ``answer_<id>``
and ungraded exercises ``exercise_<id>``. ``check_notebook.py`` (the students'
self-check, a standalone file) repeats only the ``test_`` prefix.
"""

from __future__ import annotations

TESTS = "test_"
SOLUTION = "solution_"
PUBLIC_CHECK = "public_check_"
ANSWER = "answer_"
EXERCISE = "exercise_"


def tests_grade_id(function: str) -> str:
    return TESTS + function


def solution_grade_id(function: str) -> str:
    return SOLUTION + function


def public_check_id(function: str) -> str:
    return PUBLIC_CHECK + function


def answer_grade_id(answer_id: str) -> str:
    return ANSWER + answer_id


def exercise_grade_id(name: str) -> str:
    return EXERCISE + name


def tested_function(grade_id: str | None) -> str | None:
    """The function a tests cell's grade id grades (``test_f`` -> ``f``), else None."""
    if isinstance(grade_id, str) and grade_id.startswith(TESTS) and len(grade_id) > len(TESTS):
        return grade_id[len(TESTS):]
    return None


def grade_id(cell) -> str | None:
    """A cell's grade id, None when its metadata (maybe a student's, so anything) holds no string there."""
    metadata = cell.get("metadata") if isinstance(cell, dict) else None
    meta = metadata.get("nbgrader") if isinstance(metadata, dict) else None
    gid = meta.get("grade_id") if isinstance(meta, dict) else None
    return gid if isinstance(gid, str) else None
