"""Feedback pages in nbgrader's ``feedback/<student>/<assignment>/`` so ``nbgrader release_feedback`` returns them.

nbgrader's exchange names each released page by a hash of the submission's
``submission_secret.txt``, and reads ``timestamp.txt``, both from the feedback
folder (its ``generate_feedback`` copies them from the submission): we copy them
from ``submitted/<student>/<assignment>/`` beside our pages. Both files come
from the student's side of the exchange, so they are copied only when they are
small regular files (not symlinks).
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

#: The exchange writes a timestamp and a hex secret: anything larger is not theirs.
MAX_EXCHANGE_FILE_BYTES = 4096
EXCHANGE_FILES = ("timestamp.txt", "submission_secret.txt")


def _small_regular_file(path: Path) -> bool:
    try:
        return not path.is_symlink() and path.is_file() and path.stat().st_size <= MAX_EXCHANGE_FILE_BYTES
    except OSError:
        return False


def export_feedback(out: Path, submitted: Path, feedback_root: Path, assignment: str) -> tuple[list[Path], list[str]]:
    """Copy ``out/feedback/<student>/<notebook>.html`` to ``feedback_root/<student>/<assignment>/``.

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
        for page in sorted(folder.glob("*.html")):
            shutil.copyfile(page, target / page.name)
            written.append(target / page.name)
        origin = Path(submitted) / student / assignment
        for name in EXCHANGE_FILES:
            if _small_regular_file(origin / name):
                shutil.copyfile(origin / name, target / name)
        if not (target / "submission_secret.txt").is_file() or not (target / "timestamp.txt").is_file():
            unreleasable.append(student)
    if unreleasable:
        print(f"warning: {len(unreleasable)} student(s) have no timestamp.txt/submission_secret.txt from nbgrader's exchange "
              f"(e.g. {unreleasable[0]}): their pages are in place, but nbgrader release_feedback cannot release them", file=sys.stderr)
    return written, unreleasable
