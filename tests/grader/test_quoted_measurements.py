"""The release refuses prose that quotes a measured number the notebook's experiments do not print."""

import nbformat

from grader.build.quoted_measurements import quoted_measurements, unprinted_quotes


def _executed(text: str, printed: str) -> nbformat.NotebookNode:
    code = nbformat.v4.new_code_cell("print(...)")
    code.outputs = [nbformat.v4.new_output("stream", name="stdout", text=printed)]
    return nbformat.v4.new_notebook(cells=[code, nbformat.v4.new_markdown_cell(text)])


def test_a_quote_printed_as_quoted_passes_and_one_that_is_not_is_named_with_its_cell():
    nb = _executed('The middle turns by <span class="measured">−81.2</span>° and keeps × <span class="measured">0.475</span>.',
                   "middle turned -81.2°, size × 0.475\n")
    assert quoted_measurements(nb) == [(1, "−81.2"), (1, "0.475")]
    assert unprinted_quotes(nb) == []
    stale = _executed('It keeps × <span class="measured">0.46</span> of its size.', "size × 0.475\n")
    assert unprinted_quotes(stale) == ["cell 2 quotes 0.46, which no cell prints (the closest printed number is 0.475)"]


def test_a_quote_matches_whole_numbers_only():
    nb = _executed('about <span class="measured">0.47</span>', "size × 0.475, 10.47 elsewhere\n")
    assert unprinted_quotes(nb) == ["cell 2 quotes 0.47, which no cell prints (the closest printed number is 0.475)"]


def test_the_span_is_what_students_read_as_the_bare_number():
    # nbconvert renders the markdown as HTML: the span keeps no visible trace but the number
    from nbconvert.filters.markdown import markdown2html

    html = markdown2html('× <span class="measured">0.475</span> of its size')
    assert "0.475" in html and "measured" in html and "&lt;span" not in html
