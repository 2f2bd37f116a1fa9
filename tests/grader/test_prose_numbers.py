"""A number the prose quotes is paired with what the notebook prints, to the quote's precision."""

import nbformat
from hypothesis import given, strategies as st

from tests.prose_numbers import agrees, misquoted, printed_numbers


def _executed(text: str, printed: str) -> nbformat.NotebookNode:
    code = nbformat.v4.new_code_cell("print(...)")
    code.outputs = [nbformat.v4.new_output("stream", name="stdout", text=printed)]
    return nbformat.v4.new_notebook(cells=[code, nbformat.v4.new_markdown_cell(text)])


def test_a_stale_quote_is_named_with_its_notebook_cell_and_the_printed_value():
    nb = _executed('keeps × <span class="measured">0.46</span> and turns <span class="measured">−81.2</span>°',
                   "middle turned -81.2°, size × 0.475\n")
    assert misquoted("03_arap", nb) == ["03_arap, cell 2: the prose quotes 0.46, the closest printed number is 0.475"]


def test_printed_numbers_keep_signs_percentages_and_exponents():
    nb = _executed("", "volume -13.1 % of 1547 vertices; 36% moved; energy -1.2e-10, x0 = 2\n")
    assert printed_numbers(nb) == ["-13.1", "1547", "36%", "-1.2e-10", "2"]


def test_the_tolerance_is_half_a_unit_of_the_quotes_last_digit():
    assert agrees("0.475", "0.4750") and agrees("0.475", "0.47549") and not agrees("0.475", "0.476")
    assert agrees("1.28", "1.28") and not agrees("1.28", "1.29")
    assert agrees("−13.1", "-13.1") and not agrees("−13.1", "13.1")
    assert agrees("5.0", "-5.0"), "the prose says 'loses 5.0 %' where the cell prints -5.0 %"
    assert agrees("36%", "36%") and not agrees("36", "36%")


def test_a_quote_that_is_not_a_number_is_refused():
    nb = _executed('about <span class="measured">a third</span>', "36%\n")
    assert misquoted("04_bbw", nb) == ["04_bbw, cell 2: the prose quotes 'a third', which is not a number"]


@given(st.floats(-1e4, 1e4, allow_nan=False), st.integers(0, 5))
def test_a_number_agrees_with_itself_printed_at_any_finer_precision(x, decimals):
    quote = f"{x:.{decimals}f}"
    assert agrees(quote, f"{x:.{decimals}f}") and agrees(quote, f"{float(quote):.{decimals + 2}f}")
