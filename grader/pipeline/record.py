"""Step 5: record unit results: unit files, log, feedback, gradebook, grades.csv.

Only the main process of a run records, one unit at a time. Several runs may
share one gradebook (two TAs grading halves of a class into one PostgreSQL
database): each unit's gradebook write is retried as a whole when a concurrent
run created the same student or submission first. Every file is written to a
temporary name and renamed, so a crash mid-run leaves whole files only.
"""

from __future__ import annotations

import json
import time
import warnings
from pathlib import Path

from grader.course_pack import is_bonus
from grader.spreadsheet import csv_text

#: ``bonus`` is ``true`` on the rows of bonus notebooks (BONUS_CONTRACT.md): their
#: ``max_score`` is extra credit, not part of the assignment's regular maximum.
CSV_HEADER = ("student_id", "assignment", "notebook", "score", "max_score", "bonus")


def write_text_atomic(path: Path, text: str) -> None:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)


def safe_name(student_id: str) -> str:
    """A student id as a single path component (ids are folder names, so this is the identity in practice)."""
    return student_id.replace("/", "_").replace("\x00", "_") or "_"


def unit_path(out: Path, student_id: str, notebook: str) -> Path:
    return Path(out) / "units" / safe_name(student_id) / f"{notebook}.json"


def save_unit(out: Path, result: dict) -> None:
    """Keep a unit's result (without the bulky parts) so a re-run can reuse it."""
    slim = {k: v for k, v in result.items() if k not in ("feedback_html", "autograded_notebook")}
    write_text_atomic(unit_path(out, result["student_id"], result["notebook"]), json.dumps(slim, indent=1))


def load_unit(out: Path, student_id: str, notebook: str) -> dict | None:
    try:
        return json.loads(unit_path(out, student_id, notebook).read_text())
    except (OSError, json.JSONDecodeError):
        return None


def log_record(result: dict) -> dict:
    """The ``log.jsonl`` line of one unit."""
    return {
        "student_id": result["student_id"],
        "notebook": result["notebook"],
        "status": result["status"],
        "score": result["score"],
        "max_score": result["max_score"],
        "duration_s": result.get("duration_s"),
        "execution_s": result.get("execution_s"),
        "peak_rss_bytes": result.get("peak_rss_bytes"),
        "seed": result.get("seed"),
        "reasons": result.get("reasons", []),
        "events": result.get("events", []),
        "notes": result.get("notes", []),
        "reused": result.get("reused", False),
    }


def append_log(out: Path, result: dict) -> None:
    with open(Path(out) / "log.jsonl", "a", encoding="utf-8") as fh:
        fh.write(json.dumps(log_record(result)) + "\n")
        fh.flush()


def compact_log(out: Path) -> None:
    """Keep one ``log.jsonl`` record per student × notebook: the last one (a re-run appends again)."""
    path = Path(out) / "log.jsonl"
    if not path.is_file():
        return
    last: dict[tuple, str] = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            rec = json.loads(line)
            key = (rec["student_id"], rec["notebook"])
        except (ValueError, KeyError, TypeError):
            continue  # a line cut by a crash mid-write
        last.pop(key, None)  # re-insert: the file keeps the order in which units were last graded
        last[key] = line
    write_text_atomic(path, "".join(line + "\n" for line in last.values()))


def write_feedback(out: Path, result: dict) -> None:
    if result.get("feedback_html"):
        write_text_atomic(Path(out) / "feedback" / safe_name(result["student_id"]) / f"{result['notebook']}.html", result["feedback_html"])


#: Control characters (but tab and newline) of a message: a TA's page shows text, never terminal or markup codes.
_CONTROL = dict.fromkeys([*range(0, 9), *range(11, 32), 127], None)


def verdict_text(test: dict) -> str:
    """What a tests cell shows in formgrader: its score and the feedback page's verdict per hidden case, as plain text."""
    lines = [f"{test['function']}: {test['score']:g} / {test['points']:g} points (hidden tests, judged by the grader outside "
             f"the student's kernel; this cell itself was not run)", str(test.get("summary", ""))]
    for case in test.get("cases", []):
        why = "passed" if case.get("passed") else (case.get("error") or "; ".join(case.get("failed", [])))
        lines.append(f"- {case.get('label', '')}: {why}")
    return "\n".join(lines).translate(_CONTROL) + "\n"


def with_verdicts(notebook_json: str, tests: list[dict], answers: dict | None = None, bonus: bool = False) -> str:
    """The executed notebook as formgrader shows it to a TA.

    Each tests cell gets its verdicts as its output (a text stream; formgrader
    escapes it), and each written answer in ``answers`` (grade id -> model
    answer and points, ``grader.exports.ta_notes.model_answers``) is followed by
    the TA's cell with the model answer and a rubric.
    """
    from grader.exports.ta_notes import ta_note

    nb = json.loads(notebook_json)
    by_id = {t["grade_id"]: t for t in tests}
    cells = []
    for cell in nb.get("cells", []):
        grade_id = ((cell.get("metadata") or {}).get("nbgrader") or {}).get("grade_id")
        test = by_id.get(grade_id)
        if cell.get("cell_type") == "code" and test is not None:
            cell["outputs"] = [{"output_type": "stream", "name": "stdout", "text": verdict_text(test)}]
        cells.append(cell)
        if cell.get("cell_type") == "markdown" and grade_id in (answers or {}):
            note = ta_note(*answers[grade_id], bonus=bonus)
            if nb.get("nbformat_minor", 0) >= 5:  # cell ids exist from nbformat 4.5 on; grade ids are unique
                note["id"] = f"ta-note-{grade_id}"[:64]
            else:
                del note["id"]
            cells.append(note)
    nb["cells"] = cells
    return json.dumps(nb, ensure_ascii=False)


def write_autograded(autograded: Path, result: dict) -> None:
    """The executed notebook where formgrader looks for it (``<course>/autograded``), as :func:`with_verdicts` makes it.

    Tests cells are not run when grading (their verdicts are computed outside
    the kernel), so without their verdicts formgrader would show them empty, and
    a TA grading by hand would not see why a test failed. Model answers come
    from the course's instructor notebook (``<course>/source/<assignment>/``,
    beside ``autograded/`` as nbgrader lays a course out).
    """
    from grader.exports.ta_notes import model_answers

    if result.get("autograded_notebook"):
        source = Path(autograded).parent / "source" / result["assignment"] / f"{result['notebook']}.ipynb"
        write_text_atomic(
            Path(autograded) / safe_name(result["student_id"]) / result["assignment"] / f"{result['notebook']}.ipynb",
            with_verdicts(result["autograded_notebook"], result.get("tests", []), model_answers(source), is_bonus(result["assignment"], result["notebook"])),
        )


def write_grades_csv(out: Path, results: list[dict]) -> Path:
    """``grades.csv``: one row per student × notebook, sorted."""
    rows = ([r["student_id"], r["assignment"], r["notebook"], f"{r['score']:g}", f"{r['max_score']:g}", str(is_bonus(r["assignment"], r["notebook"])).lower()]
            for r in sorted(results, key=lambda r: (r["student_id"], r["notebook"])))
    path = Path(out) / "grades.csv"
    write_text_atomic(path, csv_text(CSV_HEADER, rows))
    return path


#: Attempts of one gradebook write that lost a race with another run (unique key taken, deadlock).
GRADEBOOK_ATTEMPTS = 8


def retry_on_conflict(write, rollback, attempts: int = GRADEBOOK_ATTEMPTS):
    """``write()``, again after ``rollback()`` while a concurrent writer wins a unique key or a lock.

    Raises the last error if every attempt failed.
    """
    from nbgrader.api import InvalidEntry
    from sqlalchemy.exc import DBAPIError

    for attempt in range(attempts):
        try:
            return write()
        except (InvalidEntry, DBAPIError):
            rollback()
            if attempt == attempts - 1:
                raise
            time.sleep(0.02 * 2**attempt)


def open_gradebook(db_url: str):
    """An nbgrader ``Gradebook`` on ``db_url``, also while another run creates the same database's tables."""
    from nbgrader.api import Gradebook

    from grader.paths import COURSE_ID

    return retry_on_conflict(lambda: Gradebook(db_url, course_id=COURSE_ID), lambda: None)


def record_gradebook(gb, result: dict) -> None:
    """Store a unit's autograded scores in an open nbgrader ``Gradebook`` (retried on a lost race).

    Manually graded cells (short answers) are flagged for formgrader. A bonus
    notebook's points are nbgrader's extra credit (see :func:`bonus_as_extra_credit`).
    """
    retry_on_conflict(lambda: _record_gradebook_once(gb, result), gb.db.rollback)


def bonus_as_extra_credit(gb, assignment: str, notebook: str) -> None:
    """Give the grade cells of a bonus notebook a maximum of 0 in the gradebook (not committed).

    nbgrader has no bonus notebook, but each grade has ``extra_credit``, which counts in
    every score and in no maximum: with its cells worth 0, the bonus notebook's
    earned points, stored as extra credit, are extra credit in formgrader, the
    gradebook's totals and ``nbgrader export``. ``generate_assignment`` writes
    the notebook's points again; every grading run puts this back.
    """
    for cell in gb.find_notebook(notebook, assignment).grade_cells:
        if cell.max_score != 0:
            cell.max_score = 0.0


def _record_gradebook_once(gb, result: dict) -> None:
    sid, assignment, notebook = result["student_id"], result["assignment"], result["notebook"]
    gb.update_or_create_student(sid)
    with warnings.catch_warnings():
        # nbgrader's own submission update trips SQLAlchemy's autoflush warning; the rows are written.
        warnings.filterwarnings("ignore", message=".*not in session.*")
        gb.update_or_create_submission(assignment, sid)
    scores = {t["grade_id"]: t["score"] for t in result["tests"]}
    bonus = is_bonus(assignment, notebook)
    if bonus:
        bonus_as_extra_credit(gb, assignment, notebook)
    submitted = gb.find_submission_notebook(notebook, assignment, sid)
    for grade in submitted.grades:
        if grade.name in scores:
            if bonus:  # a bonus cell is worth 0: what it earned is extra credit
                grade.auto_score, grade.extra_credit = 0.0, scores[grade.name] or None
            else:
                grade.auto_score = scores[grade.name]
            grade.needs_manual_grade = False
        elif grade.cell.cell_type == "markdown":
            grade.auto_score = None
            grade.needs_manual_grade = result["status"] not in ("missing", "invalid")
    gb.db.commit()
