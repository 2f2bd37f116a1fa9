"""What nbgrader's gradebook holds beyond a grading run's ``grades.csv``: the points TAs gave by hand in formgrader.

A grading run records autograded scores into the gradebook; TAs then grade the
written answers there (formgrader), may change an autograded score or give
extra credit, and comment. The exports read those back so that every file a TA
or a student opens agrees with the gradebook (and with ``nbgrader export``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from grader.course_pack import is_bonus


@dataclass(frozen=True)
class HandGrade:
    """One cell's grading by hand: a written answer, or an autograded cell a TA changed or gave extra credit."""

    notebook: str
    cell: str  # the cell's grade id
    written: bool  # a written answer (markdown cell); else an autograded tests cell
    score: float | None  # the TA's score; None while not graded (written) or not changed (autograded)
    max_score: float
    auto_score: float | None = None
    extra_credit: float = 0.0  # given by a TA (a bonus notebook's earned points are not counted here)
    comment: str = ""
    pending: bool = False  # a written answer formgrader still lists as needing a grade


@dataclass
class GradebookSubmission:
    """One student's submission as the gradebook scores it."""

    student_id: str
    score: float  # nbgrader's: autograded, by hand and extra credit, before any late penalty
    max_score: float  # the assignment's (bonus cells are worth 0)
    #: per notebook, what grading recorded: the tests cells' scores and the bonus notebook's earned points
    autograded_by_notebook: dict[str, float] = field(default_factory=dict)
    hand: list[HandGrade] = field(default_factory=list)

    @property
    def autograded(self) -> float:
        return sum(self.autograded_by_notebook.values())

    @property
    def ungraded(self) -> int:
        """Written answers still waiting for a TA."""
        return sum(h.pending for h in self.hand)

    def by_notebook(self, notebook: str) -> list[HandGrade]:
        return [h for h in self.hand if h.notebook == notebook]


def read_gradebook(db_url: str, assignment: str) -> dict[str, GradebookSubmission]:
    """Every submission of ``assignment`` in the gradebook at ``db_url``, by student id ({} if it has no such assignment)."""
    from nbgrader.api import Gradebook, MissingEntry

    subs: dict[str, GradebookSubmission] = {}
    with Gradebook(db_url) as gb:
        try:
            submissions = gb.find_assignment(assignment).submissions
        except MissingEntry:
            return {}
        for submission in submissions:
            entry = GradebookSubmission(submission.student.id, float(submission.score or 0), float(submission.max_score or 0))
            for notebook in submission.notebooks:
                bonus = is_bonus(assignment, notebook.name)
                entry.autograded_by_notebook[notebook.name] = 0.0
                comments = {c.name: (c.manual_comment or "").strip() for c in notebook.comments}
                for grade in notebook.grades:
                    written = grade.cell.cell_type == "markdown"
                    extra = float(grade.extra_credit or 0)
                    if not written:
                        entry.autograded_by_notebook[notebook.name] += float(grade.auto_score or 0) + (extra if bonus else 0.0)
                    changed = not written and grade.manual_score is not None
                    ta_extra = 0.0 if (bonus and not written) else extra
                    # A written answer of a missing notebook has nothing to grade and is not listed.
                    if (written and (grade.manual_score is not None or grade.needs_manual_grade)) or changed or ta_extra \
                            or comments.get(grade.name):
                        entry.hand.append(HandGrade(
                            notebook.name, grade.name, written,
                            None if grade.manual_score is None else float(grade.manual_score), float(grade.max_score or 0),
                            None if grade.auto_score is None else float(grade.auto_score), ta_extra, comments.get(grade.name, ""),
                            written and grade.manual_score is None and bool(grade.needs_manual_grade),
                        ))
            subs[entry.student_id] = entry
    return subs
