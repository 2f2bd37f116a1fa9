"""Notes for the TA beside each written answer in formgrader: the model answer and a short rubric.

formgrader shows the autograded notebook (``<course>/autograded/...``); grading
writes there, after each written-answer cell, one markdown cell of the
instructor's own text (the answer of the source notebook, and a rubric by the
cell's points), tagged ``deformlab-ta-only``. Students never receive it:
deformlab's feedback pages are built from the verdicts, and nbgrader's
``generate_feedback`` drops the tagged cells when the course's
``nbgrader_config.py`` sets ``c.GenerateFeedback.preprocessors`` to
:func:`feedback_preprocessors`.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

from nbconvert.preprocessors import Preprocessor
from traitlets import Bool

TA_TAG = "deformlab-ta-only"


def _rubric(points: float, bonus: bool) -> list[str]:
    half = points / 2
    lines = [f"- **{points:g}**: the conclusion and the reasoning of the model answer, in the student's own words "
             "(another correct argument counts the same);",
             f"- **{half:g}**: the right conclusion with a gap or an error in the reasoning, or sound reasoning that "
             "reaches a wrong conclusion;",
             "- **0**: no answer, or neither."]
    if bonus:
        lines.append(f"\nThis answer is bonus: its cell is worth 0 in the gradebook; enter up to {points:g} points "
                     "in its **extra credit** box.")
    return lines


def ta_note(model_answer: str, points: float, bonus: bool = False) -> dict:
    """The TA's cell (an nbformat markdown cell as a dict) for a written answer worth ``points``."""
    quoted = "\n".join(f"> {line}" if line.strip() else ">" for line in model_answer.strip().splitlines())
    text = "\n".join([
        "**For the TA: not part of the student's notebook, never returned to students.**",
        "",
        f"**Model answer** ({points:g} point{'s' if points != 1 else ''}):",
        "",
        quoted,
        "",
        "**Rubric**",
        "",
        *_rubric(points, bonus),
    ])
    return {"cell_type": "markdown", "id": None, "metadata": {"tags": [TA_TAG], "deformlab": {"ta_only": True}}, "source": text}


@functools.lru_cache(maxsize=32)
def _answers(path: str, mtime_ns: int) -> dict[str, tuple[str, float]]:
    nb = json.loads(Path(path).read_text(encoding="utf-8"))
    found = {}
    for cell in nb.get("cells", []):
        meta = (cell.get("metadata") or {}).get("nbgrader") or {}
        if cell.get("cell_type") == "markdown" and meta.get("grade") and meta.get("grade_id"):
            source = cell.get("source", "")
            found[meta["grade_id"]] = ("".join(source) if isinstance(source, list) else source, float(meta.get("points") or 0))
    return found


def model_answers(source_notebook: Path) -> dict[str, tuple[str, float]]:
    """Grade id -> (model answer, points) of each written answer of an instructor (source) notebook; {} if there is none."""
    try:
        return _answers(str(source_notebook), Path(source_notebook).stat().st_mtime_ns)
    except (OSError, ValueError):
        return {}


class RemoveTANotes(Preprocessor):
    """Drop the TA's cells (:data:`TA_TAG`) from a notebook: for nbgrader's ``generate_feedback``."""

    enabled = Bool(True).tag(config=True)

    def preprocess(self, nb, resources):
        nb.cells = [c for c in nb.cells if TA_TAG not in (c.get("metadata") or {}).get("tags", [])]
        return nb, resources


def feedback_preprocessors() -> list:
    """nbgrader's ``GenerateFeedback`` preprocessors, and :class:`RemoveTANotes` last."""
    from nbconvert.preprocessors import CSSHTMLHeaderPreprocessor
    from nbgrader.preprocessors import GetGrades

    return [GetGrades, CSSHTMLHeaderPreprocessor, RemoveTANotes]
