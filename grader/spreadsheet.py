"""CSV files a spreadsheet opens as text, never as formulas.

Student ids are folder names the grader does not choose, and the class report
quotes students' error messages. A cell that begins with ``=``, ``+``, ``-``,
``@``, a tab or a carriage return is a formula to Excel, LibreOffice and Google
Sheets (CWE-1236, "CSV injection"): ``=HYPERLINK(...)`` in a student id would
run in the TA's spreadsheet. Such a cell is written behind a ``'``, which
spreadsheets take as "text" and do not show. A cell that already begins with
``'`` gets one more, so that reading back (``read_csv``) gives exactly what was
written. Numbers stay numbers: ``-0.5`` is written as it is.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Iterable, Mapping, Sequence

FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
TEXT_MARK = "'"


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def escape_cell(value) -> str:
    """``value`` as a CSV cell that no spreadsheet evaluates."""
    text = value if isinstance(value, str) else str(value)
    if text.startswith(TEXT_MARK) or (text.startswith(FORMULA_START) and not _is_number(text)):
        return TEXT_MARK + text
    return text


def unescape_cell(text: str) -> str:
    """The value ``escape_cell`` was given."""
    return text[1:] if text.startswith(TEXT_MARK) else text


def csv_text(header: Sequence[str], rows: Iterable[Sequence | Mapping]) -> str:
    """A CSV file's text: ``header`` then ``rows`` (sequences, or mappings keyed by the header), every cell escaped."""
    buf = io.StringIO()
    # RFC 4180's line end: a cell holding a bare carriage return is then quoted, not read as a line end.
    writer = csv.writer(buf, lineterminator="\r\n")
    writer.writerow([escape_cell(h) for h in header])
    for row in rows:
        cells = [row.get(h, "") for h in header] if isinstance(row, Mapping) else row
        writer.writerow([escape_cell(c) for c in cells])
    return buf.getvalue()


def read_csv(path: Path) -> list[dict[str, str]]:
    """The rows of a CSV file written by ``csv_text``, as ``{column: value}`` with the values unescaped."""
    with open(path, encoding="utf-8", newline="") as fh:
        return [{unescape_cell(k): unescape_cell(v or "") for k, v in row.items()} for row in csv.DictReader(fh)]
