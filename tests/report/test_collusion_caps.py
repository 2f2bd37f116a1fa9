"""The collusion pass is capped: oversized code is cut (and the report says so), and the pass runs in a
child process under limits, so that a limit hit or a failure costs only the report's collusion section."""

from __future__ import annotations

import shutil
from collections import Counter

import nbformat
import pytest
from hypothesis import given, strategies as st

ASSIGNMENT = "deformation"
from grader.pipeline.read_submission import MAX_NOTEBOOK_BYTES
from grader.report.class_report import CSV_TABLES, collusion_of_run, load_results, write_class_report
from grader.report.collusion import MAX_CODE_BYTES, CollusionCaps, cap_code, limited_collusion

NOTEBOOK = "02_sign_correction"
SECTIONS = ('id="notebooks"', 'id="cases"', 'id="resources"', 'id="incidents"', 'id="collusion"', "scores-per-function")


@pytest.fixture(scope="module")
def huge_class(graded_class, tmp_path_factory):
    """The graded class with ada's 02 replaced by a notebook at the submission size cap: her correct solution
    and a string literal of ``%s`` filling it (pygments makes a token of each ``%s``)."""
    paths, submitted, out, results = graded_class
    copy = tmp_path_factory.mktemp("huge") / "submitted"
    shutil.copytree(submitted, copy)
    path = copy / "ada" / ASSIGNMENT / f"{NOTEBOOK}.ipynb"
    nb = nbformat.read(path, as_version=4)
    cell = next(c for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("solution"))
    cell.source += '\nPADDING = "X"\n'
    room = MAX_NOTEBOOK_BYTES - len(nbformat.writes(nb).encode()) - 16
    cell.source = cell.source.replace('"X"', '"' + "%s" * (room // 2) + '"')
    nbformat.write(nb, path)
    assert MAX_NOTEBOOK_BYTES - 64 < path.stat().st_size <= MAX_NOTEBOOK_BYTES
    return paths, copy, out, results


def _sections(html: str) -> list[str]:
    return [s for s in SECTIONS if s in html]


def test_a_notebook_at_the_size_cap_is_cut_and_the_report_names_the_cut(huge_class, tmp_path, report_summary):
    paths, submitted, out, results = huge_class
    grades = (out / "grades.csv").read_bytes()
    evidence = collusion_of_run(out, submitted, ASSIGNMENT, paths.source_notebooks(ASSIGNMENT))
    assert evidence.missing is None
    [cut] = evidence.cuts
    assert (cut["student_id"], cut["notebook"], cut["cap"]) == ("ada", NOTEBOOK, MAX_CODE_BYTES)
    assert cut["bytes"] > MAX_NOTEBOOK_BYTES - 2**20
    # the rest of the class is compared as before: the disguised copy is still the top pair
    assert (evidence.pairs[0]["a"], evidence.pairs[0]["b"]) == ("bob", "carl")
    html = write_class_report(out, tmp_path / "report", collusion=evidence).read_text()
    assert _sections(html) == list(SECTIONS)
    assert f"ada's solution code in {NOTEBOOK} was cut at {MAX_CODE_BYTES:,} bytes (of {cut['bytes']:,})" in html
    assert (out / "grades.csv").read_bytes() == grades
    compared = Counter(r["notebook"] for r in results if r["status"] in ("graded", "graded-with-incidents"))
    budget = CollusionCaps().cpu_budget(list(compared.values()))
    assert evidence.cpu_seconds < budget and evidence.peak_rss_bytes < CollusionCaps().memory_bytes
    report_summary("collusion caps", f"collusion pass on a class with one {MAX_NOTEBOOK_BYTES / 2**20:.0f} MiB notebook: "
                   f"{evidence.cpu_seconds:.2f} CPU-s (cap {budget}), peak RSS {evidence.peak_rss_bytes / 2**20:.0f} MiB "
                   f"(cap {CollusionCaps().memory_bytes / 2**30:g} GiB more address space)")


@pytest.mark.parametrize("caps, why", [
    # uncut, the huge literal alone would take minutes of fingerprinting
    (CollusionCaps(cpu_seconds=1, cpu_seconds_per_submission=0, cpu_seconds_per_pair=0, max_code_bytes=None),
     "the collusion pass ran past its CPU cap (2 CPU-s for this class)"),
    # reading a notebook at the size cap needs more than this
    (CollusionCaps(memory_bytes=256 * 2**20), "the collusion pass needed more than its memory cap (0.25 GiB of address space)"),
], ids=["cpu", "memory"])
def test_a_collusion_pass_killed_by_its_limit_costs_only_the_collusion_section(huge_class, tmp_path, caps, why):
    paths, submitted, out, _ = huge_class
    grades = (out / "grades.csv").read_bytes()
    evidence = limited_collusion(load_results(out), submitted, paths.source_notebooks(ASSIGNMENT), ASSIGNMENT, caps)
    assert (evidence.missing, evidence.pairs, evidence.cuts) == (why, [], [])
    page = write_class_report(out, tmp_path / "report", collusion=evidence)
    html = page.read_text()
    assert _sections(html) == list(SECTIONS)
    section = html[html.index('id="collusion"'):]
    assert f"This section is missing:</strong> {why}. Everything else in this report, and grades.csv, is complete" in section
    assert "<pre>" not in section
    assert (out / "grades.csv").read_bytes() == grades
    # every table of the report (the collusion pairs have none of their own)
    assert sorted(p.stem for p in page.parent.glob("*.csv")) == sorted(CSV_TABLES)


def test_a_collusion_pass_that_fails_costs_only_the_collusion_section(graded_class, tmp_path):
    paths, submitted, out, results = graded_class
    gone = tmp_path / "02_sign_correction.ipynb"  # an instructor notebook deleted since grading
    evidence = limited_collusion(results, submitted, [gone], ASSIGNMENT)
    assert evidence.pairs == [] and evidence.missing.startswith("the collusion pass failed (exit status 1: FileNotFoundError")
    html = write_class_report(out, tmp_path / "report", collusion=evidence).read_text()
    assert _sections(html) == list(SECTIONS) and "This section is missing:</strong> the collusion pass failed" in html


def test_deformlab_report_tells_the_ta_about_the_cut(huge_class, tmp_path, capsys, monkeypatch):
    from grader.cli import main

    paths, submitted, out, _ = huge_class
    # --course sets DEFORMLAB_ROOT for the process: undone after the test, so later tests see the checkout
    monkeypatch.setenv("DEFORMLAB_ROOT", str(paths.root))
    assert main(["--course", str(paths.root), "report", str(out), "--submitted", str(submitted), "--to", str(tmp_path / "r")]) == 0
    assert capsys.readouterr().out.strip().endswith("(1 pair(s) with collusion evidence; 1 submission(s) cut at the code cap)")
    assert f"ada's solution code in {NOTEBOOK} was cut at" in (tmp_path / "r" / "index.html").read_text()


def test_a_report_made_without_the_submissions_says_the_pairs_were_not_compared(graded_class, tmp_path):
    _, _, out, _ = graded_class
    html = write_class_report(out, tmp_path / "report").read_text()
    assert "Not compared: the report was made without the submitted notebooks" in html


@given(st.text(max_size=200), st.integers(min_value=0, max_value=300))
def test_code_is_cut_at_the_cap_on_a_character_boundary_and_only_when_over_it(code, cap):
    kept, full = cap_code(code, cap)
    size = len(code.encode("utf-8", "surrogatepass"))
    if size <= cap:
        assert (kept, full) == (code, None)
    else:
        assert full == size and code.startswith(kept)
        assert cap - 3 <= len(kept.encode("utf-8", "surrogatepass")) <= cap
