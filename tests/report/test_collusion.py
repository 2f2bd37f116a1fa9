"""Collusion evidence: a disguised copy ranks first; identical wrong outputs are seen; the page shows both sides escaped."""

import nbformat

ASSIGNMENT = "deformation"
from tests.corpus import build_submission, load_corpus
from grader.report.collusion import SIMILARITY_THRESHOLD, boilerplate, class_collusion, rank_pairs, student_code
from grader.report.class_report import write_class_report

from .conftest import ROOT, rename_variables

NOTEBOOK = "02_sign_correction"


def corpus_codes(source_notebooks, tmp_path):
    """The student's own code of every corpus entry of 02 (each a different bug or method), by student."""
    source = nbformat.read(source_notebooks[NOTEBOOK], as_version=4)
    shared = boilerplate(source)
    codes = {}
    for entry in load_corpus(ROOT / "tests" / "corpus"):
        if entry.kind in ("buggy", "correct") and entry.notebook == NOTEBOOK and entry.edit is None:
            path = build_submission(entry, source_notebooks[NOTEBOOK].parent, tmp_path, entry.name)
            codes[entry.name] = student_code(path, shared)
    return codes, shared, source


def test_a_copy_with_renamed_variables_ranks_first_among_the_corpus(source_notebooks, tmp_path, report_summary):
    codes, shared, _ = corpus_codes(source_notebooks, tmp_path)
    original = tmp_path / "no_sign_correction" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    copy = rename_variables(nbformat.read(original, as_version=4), {"U": "left", "Vt": "right_t", "S": "cov"})
    copy_path = tmp_path / "copy.ipynb"
    nbformat.write(copy, copy_path)
    codes["copycat"] = student_code(copy_path, shared)
    assert codes["copycat"] != codes["no_sign_correction"]
    pairs = rank_pairs(codes, shared, notebook=NOTEBOOK)
    assert {pairs[0]["a"], pairs[0]["b"]} == {"copycat", "no_sign_correction"}
    report_summary("collusion", f"{NOTEBOOK}: {len(codes)} submissions; renamed copy similarity {pairs[0]['similarity']:.3f}; "
                   f"{len(pairs) - 1} other pair(s) above the threshold {SIMILARITY_THRESHOLD}")


def test_identical_wrong_outputs_on_a_hidden_case_are_evidence(graded_class):
    paths, submitted, out, results = graded_class
    pairs = class_collusion(results, submitted, paths.source_notebooks(ASSIGNMENT), ASSIGNMENT).pairs
    top = pairs[0]
    assert (top["a"], top["b"], top["notebook"]) == ("bob", "carl", NOTEBOOK)
    assert top["similarity"] > 0.8 and len(top["shared_wrong"]) >= 3
    assert all("optimal_rotation" in s or "rigid_align" in s for s in top["shared_wrong"])
    assert not any({"ada", "dan"} <= {p["a"], p["b"]} for p in pairs), "the instructor's code is no evidence"


def test_the_report_shows_pairs_side_by_side(graded_class):
    paths, submitted, out, results = graded_class
    evidence = class_collusion(results, submitted, paths.source_notebooks(ASSIGNMENT), ASSIGNMENT)
    html = write_class_report(out, collusion=evidence).read_text()
    section = html[html.index('id="collusion"'):]
    assert "bob and carl: 02_sign_correction" in section
    assert section.count("<pre>") == 2 * len(evidence.pairs) > 0
    assert evidence.cuts == [] and "was cut at" not in section
