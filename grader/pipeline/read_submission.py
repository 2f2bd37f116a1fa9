"""Step 1: read a student's file as a notebook, safely: no link followed, sizes capped, nesting and garbage refused.

The file and its bytes are the student's: it is read only if it is a regular
file within :data:`MAX_NOTEBOOK_BYTES`, and whatever fails to parse is a
:class:`SubmissionError` whose message is the unit's reason, never a crash.
"""

from __future__ import annotations

import errno
import json
import os
import stat
from pathlib import Path

import nbformat

__all__ = ["MAX_NOTEBOOK_BYTES", "SubmissionError", "read_submission_bytes", "read_submission", "parse_submission"]

#: A submission larger than this is not read at all.
MAX_NOTEBOOK_BYTES = 64 * 2**20


class SubmissionError(ValueError):
    """The file cannot be graded as this notebook; the message is the row's reason."""


def read_submission_bytes(path: Path) -> bytes:
    """The bytes of a submitted file: a regular file within the size cap, never read through a link.

    Raises
    ------
    SubmissionError
        If the file is missing, a link, not a regular file, or too large.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
    except OSError as exc:
        what = "the submission is a link, which is not graded" if exc.errno == errno.ELOOP else f"cannot read the submission: {exc.strerror}"
        raise SubmissionError(what) from None
    with os.fdopen(fd, "rb") as fh:
        info = os.fstat(fh.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise SubmissionError("the submission is not a regular file")
        if info.st_size > MAX_NOTEBOOK_BYTES:
            raise SubmissionError(f"the notebook is {info.st_size / 2**20:.0f} MiB, over the {MAX_NOTEBOOK_BYTES // 2**20} MiB limit")
        data = fh.read(info.st_size + 1)  # not the cap + 1: read() allocates what it is asked for
    if len(data) > MAX_NOTEBOOK_BYTES:
        raise SubmissionError(f"the notebook is over the {MAX_NOTEBOOK_BYTES // 2**20} MiB limit")
    return data


def read_submission(path: Path) -> nbformat.NotebookNode:
    """Read a submitted file as a v4 notebook (:func:`read_submission_bytes`, then :func:`parse_submission`).

    Raises
    ------
    SubmissionError
        If the file is unreadable, too large, nested too deeply, or not a notebook.
    """
    return parse_submission(read_submission_bytes(Path(path)))


def parse_submission(data: bytes) -> nbformat.NotebookNode:
    """Parse a submitted file's bytes as a v4 notebook.

    Raises
    ------
    SubmissionError
        If the bytes are too many, nested too deeply, or not a notebook.
    """
    if len(data) > MAX_NOTEBOOK_BYTES:
        raise SubmissionError(f"the notebook is over the {MAX_NOTEBOOK_BYTES // 2**20} MiB limit")
    try:
        raw = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise SubmissionError(f"not a Jupyter notebook (not valid JSON: {exc})") from None
    except RecursionError:
        raise SubmissionError("not a Jupyter notebook (its JSON is nested too deeply)") from None
    if not isinstance(raw, dict) or not isinstance(raw.get("cells"), list):
        raise SubmissionError("not a Jupyter notebook (no list of cells)")
    try:
        nb = nbformat.reads(json.dumps(raw), as_version=4)
    except Exception as exc:  # noqa: BLE001 - nbformat raises many kinds
        raise SubmissionError(f"not a readable Jupyter notebook: {exc}") from None
    for cell in nb.cells:
        if not isinstance(cell.get("source"), str) or cell.get("cell_type") not in ("code", "markdown", "raw"):
            raise SubmissionError("not a readable Jupyter notebook (malformed cell)")
    return nb
