"""Pairs each number a notebook's prose quotes with the numbers its executed cells print.

The release refuses a quote that no cell prints verbatim
(grader.build.quoted_measurements); this names, for the test's failure message,
the printed number the quote most likely meant, so an author sees both values.
"""

from __future__ import annotations

import re

import nbformat

from grader.build.quoted_measurements import quoted_measurements

#: A printed number: optional sign (ASCII or typographic minus), digits, decimals, exponent, percent sign.
NUMBER = re.compile(r"(?<![\w.])[-−+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?%?")


def _value(text: str) -> float:
    return float(text.replace("−", "-").rstrip("%"))


def _decimals(text: str) -> int:
    digits = text.rstrip("%").split("e")[0]
    return len(digits.split(".")[1]) if "." in digits else 0


def printed_numbers(nb: nbformat.NotebookNode) -> list[str]:
    """Every number the code cells' text outputs show, as printed."""
    texts = []
    for cell in nb.cells:
        for out in cell.get("outputs", []) if cell.cell_type == "code" else []:
            texts.append(out.get("text", "") if out.get("output_type") == "stream"
                         else str(out.get("data", {}).get("text/plain", "")))
    return NUMBER.findall("\n".join(texts))


def agrees(quote: str, printed: str) -> bool:
    """Whether a printed number says what the quote says, to the quote's precision.

    The tolerance is half a unit of the quote's last digit (``0.475`` agrees with
    a printed ``0.4750`` or ``0.47501``, not with ``0.476``); a quote without a sign
    agrees with a negative printed number of that size (the prose says "loses 5.0 %"
    where the cell prints ``-5.0 %``), and a percentage only with a percentage.
    """
    if quote.endswith("%") != printed.endswith("%"):
        return False
    q, p = _value(quote), _value(printed)
    if not quote.startswith(("−", "-", "+")):
        p = abs(p)
    return abs(p - q) <= 0.5 * 10.0 ** -_decimals(quote) * (1 + 1e-9)


def misquoted(name: str, nb: nbformat.NotebookNode) -> list[str]:
    """One line per quote of an executed notebook that no printed number agrees with.

    Each line names the notebook, the cell, the quote and the closest printed number
    (``"03_arap, cell 41: the prose quotes 0.46, the closest printed number is 0.475"``).
    """
    printed = printed_numbers(nb)
    problems = []
    for i, quote in quoted_measurements(nb):
        if not NUMBER.fullmatch(quote):
            problems.append(f"{name}, cell {i + 1}: the prose quotes {quote!r}, which is not a number")
            continue
        if any(agrees(quote, p) for p in printed):
            continue
        closest = min(printed, key=lambda p: abs(abs(_value(p)) - abs(_value(quote))), default=None)
        problems.append(f"{name}, cell {i + 1}: the prose quotes {quote}, the closest printed number is {closest}")
    return problems
