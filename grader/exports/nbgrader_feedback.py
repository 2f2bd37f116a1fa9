"""Feedback pages in nbgrader's ``feedback/<student>/<assignment>/`` so ``nbgrader release_feedback`` returns them.

nbgrader's exchange names each released page by a hash of the submission's
``submission_secret.txt``, and reads ``timestamp.txt``, both from the feedback
folder (its ``generate_feedback`` copies them from the submission): we copy them
from ``submitted/<student>/<assignment>/`` beside our pages. Both files come
from the student's side of the exchange, so they are copied only when they are
small regular files (not symlinks).

With the gradebook (``gradebook=``), each page's hand-graded part is replaced by
what the TAs did in formgrader: each written answer's points (or that it is
not graded yet), autograded scores a TA changed, extra credit and comments; a
re-export after more grading by hand picks up the rest.
"""

from __future__ import annotations

import html
import re
import shutil
import sys
from pathlib import Path

from grader.course_pack import is_bonus
from grader.exports.gradebook import HandGrade
from grader.pipeline.record import write_text_atomic
from grader.pipeline.submitted import linked_submission

#: The exchange writes a timestamp and a hex secret: anything larger is not theirs.
MAX_EXCHANGE_FILE_BYTES = 4096
EXCHANGE_FILES = ("timestamp.txt", "submission_secret.txt")


def _small_regular_file(path: Path) -> bool:
    try:
        return not path.is_symlink() and path.is_file() and path.stat().st_size <= MAX_EXCHANGE_FILE_BYTES
    except OSError:
        return False


_MANUAL = re.compile(r"<!-- manual -->.*?<!-- /manual -->", re.S)
#: Pages graded before the manual marks existed: their hand-graded paragraph, or where it goes.
_OLD_MANUAL = re.compile(r'<p class="manual">.*?</p>\n?', re.S)
_OLD_PLACE = "<p>The hidden tests ran"


def _points(value: float) -> str:
    return f"{value:g} point{'s' if value != 1 else ''}"


def hand_graded_html(hand: list[HandGrade], bonus: bool = False) -> str:
    """The hand-graded part of a feedback page: plain text from the gradebook, escaped."""
    if not hand:
        return ""
    items = []
    for h in hand:
        if h.written:
            what = "not graded yet" if h.score is None else f"{h.score:g} / {h.max_score:g}"
        elif h.score is not None:
            what = f"{h.score:g} / {h.max_score:g}, set by a TA (autograded: {h.auto_score or 0:g})"
        else:
            what = f"autograded {h.auto_score or 0:g} / {h.max_score:g}"
        if h.extra_credit:
            what += f", extra credit +{h.extra_credit:g}"
        if h.comment:
            what += f". TA's comment: {h.comment}"
        items.append(f'<li class="manual">{html.escape(h.cell)}: {html.escape(what)}</li>')
    written = [h for h in hand if h.written]
    given = sum(h.score or 0 for h in written) + sum(h.extra_credit for h in hand) + sum(
        (h.score - (h.auto_score or 0)) for h in hand if not h.written and h.score is not None)
    pending = sum(h.score is None for h in written)
    head = f"<b>Graded by hand:</b> {html.escape(_points(round(given, 4)))} on top of the autograded score" + (
        " (extra credit: this is a bonus notebook)" if bonus else "") + (
        f"; {pending} written answer{'s' if pending != 1 else ''} not graded yet, a later copy of this page will show {'them' if pending != 1 else 'it'}"
        if pending else "") + "."
    return f'<p class="manual">{head}</p><ul>{"".join(items)}</ul>'


def with_hand_grades(page: str, hand: list[HandGrade], bonus: bool = False) -> str:
    """``page`` with its hand-graded part (between the template's manual marks) as the gradebook holds it.

    Without any hand grading (a missing notebook's written answers), the page stays as grading wrote it.
    """
    if not hand:
        return page
    block = f"<!-- manual -->{hand_graded_html(hand, bonus)}<!-- /manual -->"
    if _MANUAL.search(page):
        return _MANUAL.sub(lambda _: block, page, count=1)
    if _OLD_MANUAL.search(page):
        return _OLD_MANUAL.sub(lambda _: block + "\n", page, count=1)
    return page.replace(_OLD_PLACE, block + "\n" + _OLD_PLACE, 1)


def export_feedback(out: Path, submitted: Path, feedback_root: Path, assignment: str,
                    gradebook: dict | None = None) -> tuple[list[Path], list[str]]:
    """Copy ``out/feedback/<student>/<notebook>.html`` to ``feedback_root/<student>/<assignment>/``.

    With ``gradebook`` (``grader.exports.gradebook.read_gradebook``), each page of a student
    it holds shows the gradebook's hand grading (:func:`with_hand_grades`).

    Returns
    -------
    written : list of Path
        The pages written.
    unreleasable : list of str
        Students whose submission has no ``submission_secret.txt`` (not collected through
        nbgrader's exchange): their pages are written, but ``release_feedback`` cannot release them.

    Raises
    ------
    FileNotFoundError
        If ``out`` holds no feedback.
    """
    pages = Path(out) / "feedback"
    if not pages.is_dir():
        raise FileNotFoundError(f"{out} holds no feedback/ folder: is it the output folder of a grading run?")
    written, unreleasable = [], []
    for folder in sorted(p for p in pages.iterdir() if p.is_dir()):
        student = folder.name
        target = Path(feedback_root) / student / assignment
        target.mkdir(parents=True, exist_ok=True)
        held = (gradebook or {}).get(student)
        for page in sorted(folder.glob("*.html")):
            if held is None:
                shutil.copyfile(page, target / page.name)
            else:
                text = with_hand_grades(page.read_text(encoding="utf-8"), held.by_notebook(page.stem), is_bonus(assignment, page.stem))
                write_text_atomic(target / page.name, text)
            written.append(target / page.name)
        origin = Path(submitted) / student / assignment
        for name in EXCHANGE_FILES if not linked_submission(origin) else ():
            if _small_regular_file(origin / name):
                shutil.copyfile(origin / name, target / name)
        if not (target / "submission_secret.txt").is_file() or not (target / "timestamp.txt").is_file():
            unreleasable.append(student)
    if unreleasable:
        print(f"warning: {len(unreleasable)} student(s) have no timestamp.txt/submission_secret.txt from nbgrader's exchange "
              f"(e.g. {unreleasable[0]}): their pages are in place, but nbgrader release_feedback cannot release them", file=sys.stderr)
    return written, unreleasable
