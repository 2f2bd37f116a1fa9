"""Late submissions: nbgrader's ``timestamp.txt`` against the due date, penalties with nbgrader's plugin semantics.

As nbgrader's ``AssignLatePenalties`` does, each notebook of a late submission
gets ``plugin.late_submission_penalty(student_id, score, seconds_late)``, where
``None`` means no penalty and the value is clamped to ``[0, score]``; a
submission without ``timestamp.txt`` is on time. Policies are nbgrader plugins:
its own ``LateSubmissionPlugin`` (``none``, ``zero``) or :class:`PerDayPenalty`
here, and any ``module:Class`` subclass of nbgrader's ``BasePlugin``.

The due date of each student is nbgrader's: the assignment's plus the
student's extension, as nbgrader keeps it on the submission in its gradebook
(``SubmittedAssignment.extension``; :func:`grant_extension`, ``deformlab
extension``). An optional late-day budget (:class:`LateDays`, configured in
``nbgrader_config.py`` as the plugin is) lets each student spend whole days,
automatically and across the course's assignments in the order of their due
dates, before any penalty applies.

Applied after grading (``deformlab grade --due ...``): ``grades.csv`` gains the
columns ``seconds_late`` (after the extension), ``late_days`` (spent on this
assignment) and ``late_penalty`` (``score`` stays the autograded score, as
nbgrader keeps both), each feedback page gains a line, and the gradebook
records the timestamp and penalty where formgrader shows them.
"""

from __future__ import annotations

import html
import importlib
import math
import re
import sys
import warnings
from dataclasses import dataclass
from datetime import datetime, timedelta
from pathlib import Path

from nbgrader.plugins import BasePlugin, LateSubmissionPlugin
from traitlets import Float, Int
from traitlets.config import Configurable

from grader.pipeline import record
from grader.pipeline.submitted import LINKED, linked_submission
from grader.settings import read_config
from grader.spreadsheet import csv_text, read_csv

#: nbgrader writes one line ("2026-11-20 10:00:00.000000 UTC"); the file comes from the student's side of the exchange.
MAX_TIMESTAMP_BYTES = 256
#: Where the feedback template leaves room for the late line.
LATE_MARK = "<!-- late -->"
_LATE_LINE = re.compile(re.escape(LATE_MARK) + r'(<p class="late">.*?</p>)?')
#: The columns the late policy adds to ``grades.csv``.
LATE_COLUMNS = ("seconds_late", "late_days", "late_penalty")
DAY = 86400


class LateDays(Configurable):
    """A budget of late days per student across the course's assignments (``c.LateDays.budget`` in nbgrader_config.py).

    A late submission spends whole days of the budget automatically, as many as
    its lateness started (26 hours late: 2 days), before any penalty applies;
    when the budget runs short, the late-submission plugin charges the lateness
    the spent days did not cover. Assignments spend in the order of their due
    dates, so regrading one never changes what an earlier one spent.
    """

    budget = Int(0, help="whole late days each student may spend across the course's assignments (0: none)").tag(config=True)


@dataclass
class Lateness:
    """One student's lateness on one assignment."""

    seconds_late: float  # after the student's extension, before late days
    extension: timedelta | None = None
    late_days: int = 0  # spent on this assignment
    late_days_left: int | None = None  # of the budget, after this assignment; None without a budget
    penalty: float = 0.0  # over all notebooks

    @property
    def charged_seconds(self) -> float:
        """The lateness the late days did not cover: what the plugin charges."""
        return max(0.0, self.seconds_late - self.late_days * DAY)


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

    assigner = AssignLatePenalties(config=read_config(config_file))
    return assigner.plugin_class(parent=assigner)


def configured_late_days(config_file: Path | None) -> int:
    """The late-day budget a course's ``nbgrader_config.py`` sets (``c.LateDays.budget``; 0 when unset)."""
    budget = LateDays(config=read_config(config_file)).budget
    if budget < 0:
        raise ValueError(f"c.LateDays.budget = {budget} in {config_file}: a budget of late days cannot be negative")
    return budget


def grant_extension(db_url: str, assignment: str, student: str, extension: timedelta | None) -> None:
    """Give ``student`` an extension on ``assignment`` in nbgrader's gradebook (``None`` or zero removes it).

    As nbgrader's ``Gradebook.grant_extension``: an extension replaces the previous
    one, it never adds to it. The student and their submission are created if the
    gradebook does not know them yet, so an extension can be granted before the
    student submits.

    Raises
    ------
    ValueError
        If the gradebook does not know ``assignment``, or ``extension`` is negative.
    """
    from nbgrader.api import MissingEntry

    if extension is not None and extension < timedelta(0):
        raise ValueError(f"an extension cannot be negative: {extension}")
    with record.open_gradebook(db_url) as gb:
        try:
            gb.find_assignment(assignment)
        except MissingEntry:
            raise ValueError(f"the gradebook has no assignment {assignment!r} (deformlab release, or nbgrader db assignment add)") from None

        def write():
            gb.update_or_create_student(student)
            with warnings.catch_warnings():
                # nbgrader's own submission creation trips SQLAlchemy's autoflush warning; the rows are written.
                warnings.filterwarnings("ignore", message=".*not in session.*")
                gb.update_or_create_submission(assignment, student)
            gb.grant_extension(assignment, student, minutes=(extension or timedelta(0)).total_seconds() / 60)

        record.retry_on_conflict(write, gb.db.rollback)


def gradebook_extensions(db_url: str, assignment: str) -> dict[str, timedelta]:
    """The extensions nbgrader's gradebook holds for ``assignment``, by student."""
    from nbgrader.api import MissingEntry

    with record.open_gradebook(db_url) as gb:
        try:
            submissions = gb.find_assignment(assignment).submissions
        except MissingEntry:
            return {}
        return {s.student.id: s.extension for s in submissions if s.extension}


def late_days_spent_before(db_url: str, assignment: str, due: datetime, budget: int) -> dict[str, int]:
    """Late days each student spent on the assignments due before ``assignment`` (``due``), as the gradebook records them.

    Each earlier submission spends the days its lateness started (nbgrader's
    ``total_seconds_late``: the timestamp against the due date and extension),
    as far as the budget goes; assignments due at the same time go by name.
    """
    spent: dict[str, int] = {}
    with record.open_gradebook(db_url) as gb:
        earlier = sorted((a for a in gb.assignments if a.duedate is not None and a.name != assignment
                          and (a.duedate, a.name) < (due, assignment)), key=lambda a: (a.duedate, a.name))
        for other in earlier:
            for submission in other.submissions:
                days = math.ceil(submission.total_seconds_late / DAY)
                sid = submission.student.id
                spent[sid] = spent.get(sid, 0) + min(days, budget - spent.get(sid, 0))
    return spent


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
    """The submission time in ``folder/timestamp.txt`` (naive UTC) and, if it could not be read, why.

    ``folder`` is ``SUBMITTED/<student>/<assignment>``; if it or the student's folder is a link, it is not read.
    """
    from nbgrader.utils import parse_utc

    if linked_submission(folder):
        return None, f"{LINKED}; treated as on time"
    path = Path(folder) / "timestamp.txt"
    if not path.exists() and not path.is_symlink():
        return None, None
    if path.is_symlink() or not path.is_file() or path.stat().st_size > MAX_TIMESTAMP_BYTES:
        return None, "timestamp.txt is not a small regular file; treated as on time"
    try:
        return parse_utc(path.read_text(encoding="utf-8").strip()), None
    except (ValueError, OverflowError, UnicodeDecodeError):
        return None, "timestamp.txt holds no readable date; treated as on time"


def _duration(seconds: float) -> str:
    days, rest = divmod(int(seconds), DAY)
    hours, rest = divmod(rest, 3600)
    return (f"{days} d " if days else "") + f"{hours} h {rest // 60} min"


def late_line(seconds_late: float, penalty: float, lateness: Lateness | None = None) -> str:
    """The feedback line of a late (or extended) notebook, as plain text."""
    lateness = lateness or Lateness(seconds_late)
    parts = []
    if lateness.extension:
        granted = _duration(lateness.extension.total_seconds())
        if seconds_late <= 0:
            return f"{granted} granted; submitted on time."
        parts.append(f"your extension: {granted}")
    parts.append(f"submitted {_duration(seconds_late)} after the due date" + (" with your extension" if lateness.extension else ""))
    if lateness.late_days_left is not None:
        parts.append(f"{lateness.late_days} late day{'s' if lateness.late_days != 1 else ''} spent on this assignment "
                     f"({lateness.late_days_left} left)")
    parts.append(f"late penalty {penalty:g} point{'s' if penalty != 1 else ''} on this notebook")
    return "; ".join(parts) + "."


def misplaced_timestamp(submitted: Path, student: str, assignment: str) -> str | None:
    """Why a student's ``timestamp.txt`` is not read although there is one, one folder above nbgrader's place."""
    folder = Path(submitted) / student
    if (folder / "timestamp.txt").exists() and not (folder / assignment / "timestamp.txt").exists():
        return (f"{student!r}: timestamp.txt is one folder too high (SUBMITTED/<student>/timestamp.txt; nbgrader's collect "
                f"puts it in SUBMITTED/<student>/{assignment}/): it is not read, and the submission counts as on time")
    return None


def previous_late_columns(out: Path) -> dict[tuple[str, str], dict]:
    """The late columns of ``OUT/grades.csv`` by (student, notebook), read before a run rewrites it."""
    try:
        rows = read_csv(Path(out) / "grades.csv")
    except FileNotFoundError:
        return {}
    return {(r["student_id"], r["notebook"]): {c: r[c] for c in LATE_COLUMNS if r.get(c)} for r in rows if r.get("seconds_late")}


def keep_late_columns(out: Path, previous: dict[tuple[str, str], dict]) -> None:
    """Put back the late columns :func:`previous_late_columns` read, after a ``--student`` run that applied no due date."""
    rows = read_csv(Path(out) / "grades.csv")
    for row in rows:
        kept = previous.get((row["student_id"], row["notebook"]), {})
        for column in LATE_COLUMNS:
            row[column] = kept.get(column, "0")
    record.write_text_atomic(Path(out) / "grades.csv", csv_text([*record.CSV_HEADER, *LATE_COLUMNS], rows))


def apply_late_policy(out: Path, submitted: Path, assignment: str, due: datetime, plugin: BasePlugin, db_url: str | None = None,
                      *, late_days: int = 0, only: str | None = None, previous: dict | None = None) -> dict[str, Lateness]:
    """Add lateness and penalties to a graded run in ``out``; returns the :class:`Lateness` of each late or extended student.

    Parameters
    ----------
    due : datetime
        The assignment's due date (naive UTC); each student's extension in the gradebook ``db_url`` is added.
    late_days : int
        The course's late-day budget per student (0: none); what earlier assignments spent is read from the gradebook.
    only : str, optional
        The one student a ``--student`` run regraded: every other row keeps its late columns from ``previous``
        (:func:`previous_late_columns` of the run before), as it keeps its scores.
    """
    out = Path(out)
    rows = read_csv(out / "grades.csv")
    extensions = gradebook_extensions(db_url, assignment) if db_url else {}
    spent_before = late_days_spent_before(db_url, assignment, due, late_days) if db_url and late_days else {}
    late: dict[str, Lateness] = {}
    times: dict[str, datetime | None] = {}
    lateness_of: dict[str, Lateness] = {}
    for row in rows:
        sid = row["student_id"]
        if only is not None and sid != only:
            kept = (previous or {}).get((sid, row["notebook"]), {})
            for column in LATE_COLUMNS:
                row[column] = kept.get(column, "0")
            continue
        if sid not in lateness_of:
            times[sid], why = read_timestamp(Path(submitted) / sid / assignment)
            why = f"{sid!r}: {why}" if why else misplaced_timestamp(submitted, sid, assignment)
            if why:
                print(f"warning: {why}", file=sys.stderr)
            extension = extensions.get(sid)
            seconds = max(0.0, (times[sid] - (due + (extension or timedelta(0)))).total_seconds()) if times[sid] else 0.0
            lateness = Lateness(seconds, extension)
            if late_days:
                left = late_days - spent_before.get(sid, 0)
                lateness.late_days = min(math.ceil(seconds / DAY), left)
                lateness.late_days_left = left - lateness.late_days
            lateness_of[sid] = lateness
        lateness = lateness_of[sid]
        penalty = None
        if lateness.charged_seconds > 0:
            score = float(row["score"])
            penalty = plugin.late_submission_penalty(sid, score, lateness.charged_seconds)
            if penalty is not None:
                penalty = min(max(float(penalty), 0.0), score)  # nbgrader's _check_late_penalty
            lateness.penalty += penalty or 0.0
        if lateness.seconds_late > 0 or lateness.extension:
            late[sid] = lateness
            page = out / "feedback" / record.safe_name(sid) / f"{row['notebook']}.html"
            if page.is_file():
                text = page.read_text(encoding="utf-8")
                label = "Late" if lateness.seconds_late > 0 else "Extension"
                line = f'{LATE_MARK}<p class="late"><b>{label}:</b> {html.escape(late_line(lateness.seconds_late, penalty or 0.0, lateness))}</p>'
                # The mark stays, followed by the current line: a re-run with another due date replaces it.
                record.write_text_atomic(page, _LATE_LINE.sub(lambda _: line, text, count=1))
        row["seconds_late"] = f"{lateness.seconds_late:g}"
        row["late_days"] = str(lateness.late_days)
        row["late_penalty"] = f"{penalty or 0:g}"
    record.write_text_atomic(out / "grades.csv", csv_text([*record.CSV_HEADER, *LATE_COLUMNS], rows))
    if db_url:
        _record_in_gradebook(db_url, assignment, due, [r for r in rows if only is None or r["student_id"] == only], times)
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
