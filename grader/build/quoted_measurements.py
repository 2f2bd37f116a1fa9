"""The numbers a notebook's prose quotes from its own experiments, checked against what the experiments print.

An author marks a measured number in a text cell as
``<span class="measured">0.475</span>`` (Jupyter renders the span as the bare
number). The release executes every instructor notebook; a quoted number that
no code cell of the executed notebook prints, exactly as quoted, is a problem
of the release: the prose says something the experiment no longer shows.
"""

from __future__ import annotations

import re

import nbformat

__all__ = ["MEASURED", "quoted_measurements", "unprinted_quotes"]

#: A measured number in a text cell; the quote is the span's text (at most 40 characters).
MEASURED = re.compile(r'<span class="measured">([^<]{1,40})</span>')
#: A number in the printed outputs (minus signs already made ``−``).
_NUMBER = re.compile(r"[−+]?\d+(?:\.\d+)?")


def quoted_measurements(nb: nbformat.NotebookNode) -> list[tuple[int, str]]:
    """``(cell index, quote)`` of every measured number the text cells quote, in order."""
    return [(i, m.group(1).strip()) for i, cell in enumerate(nb.cells) if cell.cell_type == "markdown"
            for m in MEASURED.finditer(cell.source)]


def _printed(nb: nbformat.NotebookNode) -> str:
    texts = []
    for cell in nb.cells:
        for out in cell.get("outputs", []) if cell.cell_type == "code" else []:
            if out.get("output_type") == "stream":
                texts.append(out.get("text", ""))
            elif "data" in out:
                texts.append(str(out["data"].get("text/plain", "")))
    return "\n".join(texts)


def unprinted_quotes(nb: nbformat.NotebookNode) -> list[str]:
    """What is wrong with the quotes of an executed notebook: one line per quote that no output prints.

    A quote matches where the outputs hold it as a whole number (``0.47`` does not match
    inside ``0.475``); an ASCII minus in the output matches the quote's ``−``.

    Returns
    -------
    list of str
        E.g. ``"cell 41 quotes 0.475, which no cell prints"``; empty when every quote is printed.
    """
    printed = _printed(nb).replace("-", "−")
    numbers = [float(n.replace("−", "-")) for n in _NUMBER.findall(printed)]
    problems = []
    for i, quote in quoted_measurements(nb):
        pattern = r"(?<![\d.])" + re.escape(quote.replace("-", "−")) + r"(?![\d])"
        if not re.search(pattern, printed):
            problems.append(f"cell {i + 1} quotes {quote}, which no cell prints{_closest(quote, numbers)}")
    return problems


def _closest(quote: str, numbers: list[float]) -> str:
    """`` (the closest printed number is 0.475)``, for a quote that is a number; empty otherwise."""
    try:
        value = float(quote.replace("−", "-").replace(",", ""))
    except ValueError:
        return ""
    if not numbers:
        return " (the notebook prints no number)"
    closest = min(numbers, key=lambda n: abs(n - value))
    return f" (the closest printed number is {closest:g})"
