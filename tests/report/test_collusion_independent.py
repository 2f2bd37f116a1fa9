"""Collusion evidence on independent work: thirty correct submissions written apart raise no pair.

``tests/report/independent/<notebook>/*.py`` are correct submissions in the
corpus's format, each written by a different student persona in separate
sessions that saw only the contract, the notebook's text and its stubs (never
each other's code, the teaching solutions or ``reference/``). Short functions
written from one lecture converge on the same lines; the threshold must still
not flag any pair of them, while a renamed copy among them is still found.
"""

from pathlib import Path

import nbformat
import pytest

from grader.checks import check_namespace
from grader.course_pack import pack
_COURSE = pack("deformation")
stage_functions = _COURSE.stage_functions
from tests.corpus import build_submission, load_entry
from grader.report.collusion import SIMILARITY_THRESHOLD, boilerplate, rank_pairs, student_code

from .conftest import rename_variables

HERE = Path(__file__).resolve().parent / "independent"
NOTEBOOKS = sorted(p.name for p in HERE.iterdir() if p.is_dir()) if HERE.is_dir() else []
#: Notebooks where the threshold flags a pair of independent work: a known false positive of the detector,
#: kept visible (strict: once the detector no longer flags it, the test fails until the entry goes).
FLAGGED = {
    "03_arap": "since ARAP split into 03 and 03b, 03 alone holds six short functions, and two independent "
               "loop-style students (a_02, b_05: per-triangle loops the notebook's text suggests) reach about "
               "0.75 >= SIMILARITY_THRESHOLD; the threshold does not scale with how much code a notebook asks for",
}


def _flagged(notebook):
    marks = [pytest.mark.xfail(strict=True, reason=FLAGGED[notebook])] if notebook in FLAGGED else []
    return pytest.param(notebook, marks=marks)


def entries(notebook):
    return [load_entry(p, kind="correct") for p in sorted((HERE / notebook).glob("*.py"))]


@pytest.mark.parametrize("path", sorted(HERE.glob("*/*.py")), ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_every_independent_submission_is_correct(path):
    entry = load_entry(path, kind="correct")
    namespace = {}
    for source in entry.solutions.values():
        exec(compile(source, str(path), "exec"), namespace)
    assert set(stage_functions(entry.notebook)) <= set(entry.solutions)
    results = {fn: check_namespace(fn, namespace) for fn in entry.solutions}  # 03's pasted optimal_rotation too
    assert not {fn: r.summary() for fn, r in results.items() if r.fraction < 1.0}


def codes_of(notebook, source_notebooks, tmp_path):
    source = nbformat.read(source_notebooks[notebook], as_version=4)
    shared = boilerplate(source)
    codes, paths = {}, {}
    for entry in entries(notebook):
        paths[entry.name] = build_submission(entry, source_notebooks[notebook].parent, tmp_path, entry.name)
        codes[entry.name] = student_code(paths[entry.name], shared)
    return codes, shared, paths


@pytest.mark.parametrize("notebook", [_flagged(n) for n in NOTEBOOKS])
def test_thirty_independent_correct_submissions_raise_no_pair(notebook, source_notebooks, tmp_path, report_summary):
    codes, shared, _ = codes_of(notebook, source_notebooks, tmp_path)
    assert len(codes) >= 30 and all(codes.values())
    scores = rank_pairs(codes, shared, notebook=notebook)
    every = sorted((p["similarity"] for p in rank_pairs(codes, shared, notebook=notebook, similarity_threshold=0.0)), reverse=True)
    report_summary(f"collusion, independent work, {notebook}", f"{len(codes)} independent correct submissions, {len(every)} pairs; "
                   f"highest similarity {every[0]:.3f}, 10th {every[9]:.3f}; pairs above {SIMILARITY_THRESHOLD}: {len(scores)}")
    assert scores == [], [(p["a"], p["b"], p["similarity"]) for p in scores]


@pytest.mark.parametrize("notebook", NOTEBOOKS)
def test_a_renamed_copy_among_them_still_ranks_first(notebook, source_notebooks, tmp_path):
    codes, shared, paths = codes_of(notebook, source_notebooks, tmp_path)
    original = sorted(codes)[len(codes) // 2]
    nb = nbformat.read(paths[original], as_version=4)
    renames = {"V": "verts", "F": "tris", "P": "pts", "Q": "qts", "S": "cov", "R": "rot", "U": "deformed", "w": "wts"}
    copy = tmp_path / "copy.ipynb"
    nbformat.write(rename_variables(nb, renames), copy)
    codes["copycat"] = student_code(copy, shared)
    assert codes["copycat"] != codes[original]
    pairs = rank_pairs(codes, shared, notebook=notebook)
    assert pairs and {pairs[0]["a"], pairs[0]["b"]} == {"copycat", original}
