"""Late submissions: nbgrader's ``timestamp.txt`` against the due date, penalties with nbgrader's plugin semantics.

As nbgrader's ``AssignLatePenalties`` does, each notebook of a late submission
gets ``plugin.late_submission_penalty(student_id, score, seconds_late)``, where
``None`` means no penalty and the value is clamped to ``[0, score]``; a
submission without ``timestamp.txt`` is on time. Policies are nbgrader plugins:
its own ``LateSubmissionPlugin`` (``none``, ``zero``) or :class:`PerDayPenalty`
here, and any ``module:Class`` subclass of nbgrader's ``BasePlugin``.

Applied after grading (``deformlab grade --due ...``): ``grades.csv`` gains the
columns ``seconds_late`` and ``late_penalty`` (``score`` stays the autograded
score, as nbgrader keeps both), each feedback page gains a line, and the
gradebook records the timestamp and penalty where formgrader shows them.
"""

from __future__ import annotations

import html
import importlib
import math
import re
from datetime import datetime
from pathlib import Path

from nbgrader.plugins import BasePlugin, LateSubmissionPlugin
from traitlets import Float

from grader.pipeline import record
from grader.spreadsheet import csv_text, read_csv

#: nbgrader writes one line ("2026-11-20 10:00:00.000000 UTC"); the file comes from the student's side of the exchange.
MAX_TIMESTAMP_BYTES = 256
#: Where the feedback template leaves room for the late line.
LATE_MARK = "<!-- late -->"
_LATE_LINE = re.compile(re.escape(LATE_MARK) + r'(<p class="late">.*?</p>)?')


class PerDayPenalty(LateSubmissionPlugin):
    """A fraction of the notebook's score per started day late (``fraction_per_day``), after ``grace_seconds``."""

    fraction_per_day = Float(0.1, help="fraction of the score lost per started day late").tag(config=True)
    grace_seconds = Float(0.0, help="lateness forgiven, in seconds").tag(config=True)

    def late_submission_penalty(self, student_id: str, score: float, total_seconds_late: float) -> float | None:
        late = total_seconds_late - self.grace_seconds
        if late <= 0:
            return None
        return score * min(1.0, self.fraction_per_day * math.ceil(late / 86400))


def make_plugin(spec: str) -> BasePlugin:
    """The plugin a ``--late-policy`` names: ``none``, ``zero``, ``per-day:FRACTION`` or ``module:Class``.

    Raises
    ------
    ValueError
        If ``spec`` names no usable plugin.
    """
    if spec in ("none", "zero"):
        return LateSubmissionPlugin(penalty_method=spec)
    if spec.startswith("per-day:"):
        try:
            fraction = float(spec.split(":", 1)[1])
        except ValueError:
            fraction = -1.0
        if not 0 <= fraction <= 1:
            raise ValueError(f"late policy {spec!r}: per-day needs a fraction between 0 and 1, e.g. per-day:0.1")
        return PerDayPenalty(fraction_per_day=fraction)
    module, _, name = spec.partition(":")
    try:
        cls = getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError, ValueError):
        cls = None
    if not (isinstance(cls, type) and issubclass(cls, BasePlugin) and hasattr(cls, "late_submission_penalty")):
        raise ValueError(f"late policy {spec!r}: expected none, zero, per-day:FRACTION or module:Class of an nbgrader late-submission plugin")
    return cls()


def configured_plugin(config_file: Path | None) -> BasePlugin:
    """The late-submission plugin a course's ``nbgrader_config.py`` sets, as ``nbgrader autograde`` builds it.

    ``c.AssignLatePenalties.plugin_class`` names the class (nbgrader's
    ``LateSubmissionPlugin`` when unset) and the file configures it, e.g.
    ``c.LateSubmissionPlugin.penalty_method = "zero"`` or
    ``c.PerDayPenalty.fraction_per_day = 0.1``.
    """
    from nbgrader.preprocessors import AssignLatePenalties
    from traitlets.config import Config
    from traitlets.config.loader import PyFileConfigLoader

    config = Config()
    if config_file is not None and Path(config_file).is_file():
        config = PyFileConfigLoader(Path(config_file).name, path=str(Path(config_file).parent)).load_config()
    assigner = AssignLatePenalties(config=config)
    return assigner.plugin_class(parent=assigner)


def gradebook_due(db_url: str, assignment: str) -> datetime | None:
    """The due date nbgrader's gradebook holds for ``assignment`` (``nbgrader db assignment add NAME --duedate=...``)."""
    from nbgrader.api import MissingEntry

    # Another run may be creating this database's tables right now: open it as grading does.
    with record.open_gradebook(db_url) as gb:
        try:
            return gb.find_assignment(assignment).duedate
        except MissingEntry:
            return None


def parse_due(text: str) -> datetime:
    """A due date as nbgrader reads one (naive UTC), e.g. ``2026-11-20 23:59:00 Europe/Paris``.

    Raises
    ------
    ValueError
        If the text is not a date.
    """
    from nbgrader.utils import parse_utc

    try:
        return parse_utc(text)
    except (ValueError, OverflowError) as exc:
        raise ValueError(f"--due {text!r} is not a date (e.g. '2026-11-20 23:59:00 UTC'): {exc}") from None


def read_timestamp(folder: Path) -> tuple[datetime | None, str | None]:
    """The submission time in ``folder/timestamp.txt`` (naive UTC) and, if it could not be read, why."""
    from nbgrader.utils import parse_utc

    path = Path(folder) / "timestamp.txt"
    if not path.exists() and not path.is_symlink():
        return None, None
    if path.is_symlink() or not path.is_file() or path.stat().st_size > MAX_TIMESTAMP_BYTES:
        return None, "timestamp.txt is not a small regular file; treated as on time"
    try:
        return parse_utc(path.read_text(encoding="utf-8").strip()), None
    except (ValueError, OverflowError, UnicodeDecodeError):
        return None, "timestamp.txt holds no readable date; treated as on time"


def late_line(seconds_late: float, penalty: float) -> str:
    days, rest = divmod(int(seconds_late), 86400)
    hours, rest = divmod(rest, 3600)
    when = (f"{days} d " if days else "") + f"{hours} h {rest // 60} min"
    return f"submitted {when} after the due date; late penalty {penalty:g} point{'s' if penalty != 1 else ''} on this notebook."


def apply_late_policy(out: Path, submitted: Path, assignment: str, due: datetime, plugin: BasePlugin, db_url: str | None = None) -> dict:
    """Add lateness and penalties to a graded run in ``out``; returns ``{student: (seconds_late, total_penalty)}`` of late students."""
    out = Path(out)
    rows = read_csv(out / "grades.csv")
    late: dict[str, tuple[float, float]] = {}
    times: dict[str, datetime | None] = {}
    for row in rows:
        sid = row["student_id"]
        if sid not in times:
            times[sid], _ = read_timestamp(Path(submitted) / sid / assignment)
        stamp = times[sid]
        seconds = max(0.0, (stamp - due).total_seconds()) if stamp else 0.0
        penalty = None
        if seconds > 0:
            score = float(row["score"])
            penalty = plugin.late_submission_penalty(sid, score, seconds)
            if penalty is not None:
                penalty = min(max(float(penalty), 0.0), score)  # nbgrader's _check_late_penalty
            previous = late.get(sid, (seconds, 0.0))
            late[sid] = (seconds, previous[1] + (penalty or 0.0))
            page = out / "feedback" / record.safe_name(sid) / f"{row['notebook']}.html"
            if page.is_file():
                text = page.read_text(encoding="utf-8")
                line = f'{LATE_MARK}<p class="late"><b>Late:</b> {html.escape(late_line(seconds, penalty or 0.0))}</p>'
                # The mark stays, followed by the current line: a re-run with another due date replaces it.
                record.write_text_atomic(page, _LATE_LINE.sub(lambda _: line, text, count=1))
        row["seconds_late"] = f"{seconds:g}"
        row["late_penalty"] = f"{penalty or 0:g}"
    record.write_text_atomic(out / "grades.csv", csv_text([*record.CSV_HEADER, "seconds_late", "late_penalty"], rows))
    if db_url:
        _record_in_gradebook(db_url, assignment, due, rows, times)
    return late


def _record_in_gradebook(db_url: str, assignment: str, due: datetime, rows: list[dict], times: dict) -> None:
    """Due date, timestamps and penalties where formgrader shows them (nbgrader's own columns)."""
    from nbgrader.api import MissingEntry

    with record.open_gradebook(db_url) as gb:
        gb.find_assignment(assignment).duedate = due
        for row in rows:
            try:
                submission = gb.find_submission(assignment, row["student_id"])
                notebook = gb.find_submission_notebook(row["notebook"], assignment, row["student_id"])
            except MissingEntry:
                continue
            submission.timestamp = times.get(row["student_id"])
            notebook.late_submission_penalty = float(row["late_penalty"]) or None
        gb.db.commit()
