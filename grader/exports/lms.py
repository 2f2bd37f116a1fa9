"""Gradebook CSV files for Canvas and Moodle, from a grading run's ``grades.csv`` (``deformlab export``).

One number per student: the assignment's score as nbgrader's gradebook holds it
(autograded, graded by hand in formgrader, extra credit; the bonus notebook's
points are extra credit, allowed above the points possible by both systems),
minus any late penalty recorded in ``grades.csv``: the number ``nbgrader
export`` gives. A student the gradebook does not hold (or a run exported
without one) gets the autograded score of ``grades.csv``. Moodle's file also
carries a feedback column saying how late, how many late days were spent, what
lateness cost and what was graded by hand.

Canvas (Grades > Import): identity columns ``Student, ID, SIS User ID, SIS Login
ID, Section``, then one column per assignment, with an optional second row
``Points Possible``. Canvas matches rows on ``ID`` or the SIS ids; with a
``roster`` (Canvas's own gradebook export) each student's row carries Canvas's
identity columns, found where the nbgrader id equals the SIS Login ID, the SIS
User ID or the ID; without it the nbgrader id fills both SIS columns.

Moodle (Grades > Import > CSV file): a user identifier column, mapped on import
to ``idnumber``, ``username`` or ``email``, and one column per grade item; an
optional feedback column maps to the item's feedback.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

from grader.spreadsheet import csv_text, read_csv

CANVAS_IDENTITY = ("Student", "ID", "SIS User ID", "SIS Login ID", "Section")


@dataclass
class Total:
    student_id: str
    score: float
    max_score: float  # regular notebooks only: bonus is extra credit
    late_penalty: float = 0.0
    seconds_late: float = 0.0  # after the student's extension
    late_days: int = 0  # of the course's budget, spent on this assignment
    hand: float | None = None  # points the gradebook adds to the autograded score (by hand, extra credit); None: not read
    ungraded: int = 0  # written answers still waiting for a TA
    autograded: float = 0.0  # grades.csv's, before the late penalty

    def note(self) -> str:
        """What a student reads beside the number (Moodle's feedback column): lateness, late days, penalty, hand grading."""
        parts = []
        if self.seconds_late > 0:
            parts.append(f"submitted {self.seconds_late / 3600:.1f} h late")
            if self.late_days:
                parts.append(f"{self.late_days} late day{'s' if self.late_days != 1 else ''} spent")
            parts.append(f"late penalty {self.late_penalty:g} points")
        if self.hand:
            parts.append(f"{self.hand:g} points graded by hand")
        if self.ungraded:
            parts.append(f"{self.ungraded} written answer{'s' if self.ungraded != 1 else ''} not graded yet")
        return "; ".join(parts)


def totals(grades_csv: Path, gradebook: dict | None = None) -> list[Total]:
    """Per student: the assignment's score (after late penalties) and its regular maximum.

    Parameters
    ----------
    gradebook : dict, optional
        ``grader.exports.gradebook.read_gradebook``: each student it holds is scored as the
        gradebook scores them (hand grading and extra credit included), against the
        assignment's maximum there (written answers included).

    Raises
    ------
    FileNotFoundError
        If ``grades_csv`` does not exist.
    """
    by_student: dict[str, Total] = {}
    recorded: dict[str, dict[str, float]] = {}
    for row in read_csv(grades_csv):
        t = by_student.setdefault(row["student_id"], Total(row["student_id"], 0.0, 0.0))
        t.autograded += float(row["score"])
        recorded.setdefault(row["student_id"], {})[row["notebook"]] = float(row["score"])
        if row.get("bonus") != "true":  # grades.csv says which notebooks are extra credit
            t.max_score += float(row["max_score"])
        t.late_penalty += float(row.get("late_penalty") or 0)
        t.seconds_late = max(t.seconds_late, float(row.get("seconds_late") or 0))
        t.late_days = max(t.late_days, int(row.get("late_days") or 0))
    for t in by_student.values():
        held = (gradebook or {}).get(t.student_id)
        score = t.autograded
        if held is not None and _agrees(held, recorded[t.student_id]):
            score, t.max_score = held.score, held.max_score
            t.hand, t.ungraded = round(held.score - held.autograded, 4), held.ungraded
        t.score = max(0.0, round(score - t.late_penalty, 4))
    return [by_student[s] for s in sorted(by_student)]


def _agrees(held, recorded: dict[str, float]) -> bool:
    """Whether the gradebook's submission is the one ``grades.csv`` recorded: the same notebooks, the same autograded points."""
    return set(held.autograded_by_notebook) == set(recorded) and all(
        abs(held.autograded_by_notebook[nb] - score) <= 1e-6 for nb, score in recorded.items())


def disagreements(grades_csv: Path, gradebook: dict) -> list[str]:
    """Students the gradebook holds otherwise than ``grades.csv`` (another run, another course: another --db).

    :func:`totals` scores them from ``grades.csv`` alone.
    """
    recorded: dict[str, dict[str, float]] = {}
    for row in read_csv(grades_csv):
        recorded.setdefault(row["student_id"], {})[row["notebook"]] = float(row["score"])
    return [sid for sid, scores in sorted(recorded.items()) if sid in gradebook and not _agrees(gradebook[sid], scores)]


def _read_roster(roster: Path) -> list[dict]:
    with open(roster, encoding="utf-8-sig", newline="") as fh:
        rows = list(csv.DictReader(fh))
    missing = [c for c in CANVAS_IDENTITY if rows and c not in rows[0]]
    if not rows or missing:
        raise ValueError(f"{roster} is not a Canvas gradebook export: missing column(s) {', '.join(missing) or 'all (empty file)'}")
    return [r for r in rows if r["Student"].strip() not in ("Points Possible", "Student, Test")]


def canvas_csv(rows: list[Total], column: str, roster: Path | None = None) -> tuple[str, list[str]]:
    """Canvas's gradebook import file and the nbgrader ids it could not place.

    Parameters
    ----------
    column : str
        The assignment's column, as Canvas names it (``Deformation (12345)`` updates
        assignment 12345; a new name creates an assignment).
    roster : Path, optional
        Canvas's gradebook export, to carry Canvas's own identity columns.
    """
    top = max((t.max_score for t in rows), default=0)
    lines = [["Points Possible", "", "", "", "", f"{top:g}"]]
    unmatched = []
    if roster is None:
        lines += [["", "", t.student_id, t.student_id, "", f"{t.score:g}"] for t in rows]
        return csv_text([*CANVAS_IDENTITY, column], lines), unmatched
    people = _read_roster(roster)
    index = {}
    for person in people:
        for key in ("SIS Login ID", "SIS User ID", "ID"):
            if person[key].strip():
                index.setdefault(person[key].strip(), person)
    for t in rows:
        person = index.get(t.student_id)
        if person is None:
            unmatched.append(t.student_id)
            continue
        lines.append([person[c] for c in CANVAS_IDENTITY] + [f"{t.score:g}"])
    return csv_text([*CANVAS_IDENTITY, column], lines), unmatched


def moodle_csv(rows: list[Total], item: str, identifier: str = "ID number", feedback: dict[str, str] | None = None) -> str:
    """Moodle's CSV grade import file: ``identifier, item[, Feedback]``, one row per student.

    Parameters
    ----------
    item : str
        The grade item's name (mapped to the item on import).
    identifier : str
        Header of the id column (``ID number``, ``Username`` or ``Email address``, as the nbgrader ids are).
    feedback : dict, optional
        Student id -> feedback text (mapped to the item's feedback on import).
    """
    header = [identifier, item] + (["Feedback"] if feedback is not None else [])
    return csv_text(header, ([t.student_id, f"{t.score:g}"] + ([feedback.get(t.student_id, "")] if feedback is not None else [])
                             for t in rows))
