"""The student folders of a submitted folder, in nbgrader's ``submitted/<student>/<assignment>/`` layout."""

from __future__ import annotations

import sys
from pathlib import Path

#: What a student's row says when their folder is a link.
LINKED = "the submission folder is a link, which is not followed"


def linked_submission(folder: Path) -> bool:
    """Whether ``folder``, ``SUBMITTED/<student>/<assignment>``, or the student's folder above it is a link.

    Opening a file without following links (``O_NOFOLLOW``) guards its last
    path component only: through a linked folder a reader would reach any file
    of the right name elsewhere on the host (the instructor's notebooks, another
    student's ``timestamp.txt``). Nothing in such a folder is read.
    """
    folder = Path(folder)
    return folder.is_symlink() or folder.parent.is_symlink()


def student_folders(submitted: Path, assignment: str) -> dict[str, Path]:
    """Student id -> folder, for every sub-folder of ``submitted`` that holds ``<assignment>/``.

    A folder without it is not a submission of this assignment (an output folder,
    a stray download): it is named on stderr and left out, so it never becomes a
    student of the gradebook.

    Raises
    ------
    ValueError
        If no sub-folder holds ``<assignment>/``: ``submitted`` is most likely the wrong folder.
    """
    found, skipped = _scan(Path(submitted), assignment)
    if skipped:
        print(
            f"warning: skipped {len(skipped)} folder(s) of {submitted} without a {assignment}/ sub-folder: "
            + ", ".join(skipped[:10]) + (", ..." if len(skipped) > 10 else ""),
            file=sys.stderr,
        )
    return found


def check_submitted(submitted: Path, assignment: str) -> None:
    """Refuse a ``submitted`` folder that holds no student folder of ``assignment``, before anything is built.

    Raises
    ------
    ValueError
        Naming the folder and its sub-folders.
    """
    _scan(Path(submitted), assignment)


def _scan(submitted: Path, assignment: str) -> tuple[dict[str, Path], list[str]]:
    found, skipped = {}, []
    for path in sorted(submitted.iterdir()):
        if not path.is_dir() or path.name.startswith("."):
            continue
        if (path / assignment).is_dir():
            found[path.name] = path
        else:
            skipped.append(path.name)
    if not found:
        raise ValueError(
            f"{submitted} holds no <student>/{assignment}/ folder: SUBMITTED must be nbgrader's submitted folder, "
            f"one folder per student with the notebooks in <student>/{assignment}/"
            + (f" (its sub-folders: {', '.join(skipped[:5])}{', ...' if len(skipped) > 5 else ''})" if skipped else "")
        )
    return found, skipped
