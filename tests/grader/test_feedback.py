"""The feedback page: the real maximum, hand-graded points announced, readable labeled pictures, nothing from students as markup."""

import base64
import re
import struct

import nbformat
import pytest

from tests.corpus import student_notebook
from grader.pipeline.unit import UnitSpec, grade_unit, load_submission

NOTEBOOK = "04_bbw"


def spec(source_notebooks, submission, student_id="ada", notebook=NOTEBOOK):
    content, digest, error = load_submission(submission)
    return UnitSpec(student_id=student_id, notebook=notebook, submission=content, source=source_notebooks[notebook].read_text(),
                    seed=11, timeout=60, submission_sha256=digest, submission_error=error)


def max_score(source_notebooks, notebook=NOTEBOOK):
    from grader.pipeline.verify import graded_cells

    return sum(c.points for c in graded_cells(nbformat.read(source_notebooks[notebook], as_version=4)))


@pytest.fixture(scope="module")
def buggy_page(source_notebooks, tmp_path_factory, repo_root):
    """A bbw that forgets to normalize: pictures are drawn for the functions that lost points only."""
    from tests.corpus import load_entry

    entry = load_entry(repo_root / "tests" / "corpus" / "buggy" / "bbw_not_normalized.py")
    path = tmp_path_factory.mktemp("bbw") / f"{NOTEBOOK}.ipynb"
    nbformat.write(student_notebook(nbformat.read(source_notebooks[NOTEBOOK], as_version=4), entry.solutions), path)
    return grade_unit(spec(source_notebooks, path))


def test_a_missing_notebook_shows_the_real_maximum(source_notebooks):
    page = grade_unit(spec(source_notebooks, None))["feedback_html"]
    assert f"0.00 / {max_score(source_notebooks):g}</b>" in page
    assert "0.00 / 0.00" not in page


def test_an_invalid_notebook_shows_the_real_maximum(source_notebooks, tmp_path):
    bad = tmp_path / f"{NOTEBOOK}.ipynb"
    bad.write_text("{not json")
    result = grade_unit(spec(source_notebooks, bad))
    assert result["status"] == "invalid"
    assert f"0.00 / {max_score(source_notebooks):g}</b>" in result["feedback_html"]


def test_the_page_declares_its_language_and_names_the_hand_graded_points(source_notebooks):
    page = grade_unit(spec(source_notebooks, None))["feedback_html"]
    assert re.search(r"<html lang=\"en\">", page)
    manual = re.search(r"<p class=\"manual\">(.*?)</p>", page, re.S).group(1)
    assert manual.startswith("4 more points") and "answer_negative_lobes" in manual and "answer_inverse_distance" in manual


def test_everything_from_the_student_is_text_not_markup(source_notebooks, tmp_path):
    from grader.pipeline.feedback import feedback_html

    hostile = "<img src=x onerror=alert(1)>"
    page = feedback_html(spec(source_notebooks, None, student_id=hostile), [], [f"cell 3: {hostile}<script>alert(2)</script>"])
    assert "<img src=x" not in page and "<script>" not in page
    assert "&lt;img src=x onerror=alert(1)&gt;" in page


def png_size(b64):
    raw = base64.b64decode(b64)
    assert raw[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", raw[16:24])


@pytest.mark.slow
def test_pictures_are_large_labeled_and_described(buggy_page):
    page = buggy_page["feedback_html"]
    assert 0 < buggy_page["score"] < buggy_page["max_score"]
    figures = re.findall(r'<figure>\s*<img src="data:image/png;base64,([^"]+)" alt="([^"]+)">\s*<figcaption>([^<]+)</figcaption>', page)
    assert figures, "a bbw page shows the weights"
    for b64, alt, caption in figures:
        width, height = png_size(b64)
        assert width >= 800 and height >= 300, "readable, not a thumbnail"
        assert "yours" in caption.lower() or "your" in caption.lower()
        assert len(alt) > 30
