"""A small real class, graded once for the report, export and collusion tests.

Two notebooks only (a course folder with just their source notebooks) keep it to
about ten work units: a student with the reference solutions, one with the
``no_sign_correction`` bug, a copy of that student with renamed variables, a
blank release, an unreadable file under a hostile id, and one who handed in
nothing for 02.
"""

from __future__ import annotations

import re
import shutil
import tempfile
from pathlib import Path

import nbformat
import pytest
from tests.course_copy import copy_course_config

ASSIGNMENT = "deformation"
from tests.corpus import build_submission, load_entry, student_notebook
from grader.paths import CoursePaths

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = ("01_shape_matching", "02_sign_correction")
HOSTILE_ID = "eve<img src=x onerror=alert(1)>"


def released(source: nbformat.NotebookNode) -> nbformat.NotebookNode:
    from nbgrader.preprocessors import ClearHiddenTests, ClearSolutions

    nb, _ = ClearSolutions(code_stub={"python": "# YOUR CODE HERE\nraise NotImplementedError()"}).preprocess(source, {})
    nb, _ = ClearHiddenTests().preprocess(nb, {})
    return nb


def rename_variables(nb: nbformat.NotebookNode, renames: dict[str, str]) -> nbformat.NotebookNode:
    """A copied notebook with its local variables renamed, as a student hiding a copy would."""
    for cell in nb.cells:
        if (cell.metadata.get("nbgrader") or {}).get("solution"):
            for old, new in renames.items():
                cell.source = re.sub(rf"\b{old}\b", new, cell.source)
    return nb


@pytest.fixture(scope="session")
def small_course(source_notebooks, tmp_path_factory) -> CoursePaths:
    root = Path(tempfile.mkdtemp(prefix="dl-course-"))
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    target = root / "assignments" / "source" / ASSIGNMENT
    target.mkdir(parents=True)
    copy_course_config(root / "assignments")
    for nb in NOTEBOOKS:
        shutil.copy(source_notebooks[nb], target)
    yield CoursePaths(root)
    shutil.rmtree(root, ignore_errors=True)


@pytest.fixture(scope="session")
def graded_class(small_course):
    """``(paths, submitted, out, results)`` of the small class, graded with seed 5."""
    from grader.pipeline.run import GradeOptions, grade_class

    paths = small_course
    sources = paths.source_notebooks(ASSIGNMENT)
    submitted = paths.root / "submitted"
    for sid in ("ada", "blank", HOSTILE_ID):
        (submitted / sid / ASSIGNMENT).mkdir(parents=True)
    for src in sources:
        source = nbformat.read(src, as_version=4)
        nbformat.write(student_notebook(source, {}), submitted / "ada" / ASSIGNMENT / src.name)
        nbformat.write(released(source), submitted / "blank" / ASSIGNMENT / src.name)
        (submitted / HOSTILE_ID / ASSIGNMENT / src.name).write_bytes(b"\x00 not a notebook")
    entry = load_entry(ROOT / "tests" / "corpus" / "buggy" / "no_sign_correction.py")
    build_submission(entry, sources[0].parent, submitted, "bob")
    copied = rename_variables(nbformat.read(submitted / "bob" / ASSIGNMENT / f"{entry.notebook}.ipynb", as_version=4),
                              {"U": "left", "Vt": "right_t", "S": "cov"})
    (submitted / "carl" / ASSIGNMENT).mkdir(parents=True)
    nbformat.write(copied, submitted / "carl" / ASSIGNMENT / f"{entry.notebook}.ipynb")
    for sid in ("bob", "carl"):
        shutil.copy(submitted / "ada" / ASSIGNMENT / "01_shape_matching.ipynb", submitted / sid / ASSIGNMENT)
    (submitted / "dan" / ASSIGNMENT).mkdir(parents=True)
    shutil.copy(submitted / "ada" / ASSIGNMENT / "01_shape_matching.ipynb", submitted / "dan" / ASSIGNMENT)
    out = paths.root / "out"
    results = grade_class(submitted, out, GradeOptions(workers=2, seed=5, db_url=f"sqlite:///{paths.root}/gb.db", progress=False,
                                                       autograded=paths.root / "autograded"), paths)
    return paths, submitted, out, results
