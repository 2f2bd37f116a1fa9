"""Score tables printed after grading: per student when the class is small, per notebook always."""

from __future__ import annotations

import statistics
from collections import defaultdict

from grader.course_pack import is_bonus
from starter.library_policy import OWN, forbidden

#: Above this many students, ``grade`` prints per-notebook statistics only (grades.csv has every row).
MAX_STUDENT_ROWS = 40


def _bonus_notebooks(results: list[dict]) -> set[str]:
    """The notebooks whose points are extra credit in their rows' assignment (its course pack says)."""
    return {r["notebook"] for r in results if is_bonus(r.get("assignment"), r["notebook"])}


def score_table(results: list[dict], students: list[str], notebooks: list[str]) -> str:
    """Students × notebooks scores (``score/max``), each student's regular total and bonus, as aligned text."""
    by_unit = {(r["student_id"], r["notebook"]): r for r in results}
    bonus_notebooks = _bonus_notebooks(results)
    width = max(len(s) for s in students)
    heads = [nb.split("_", 1)[0] + ("+" if nb in bonus_notebooks else "") for nb in notebooks]
    lines = [f"{'student':<{width}}  " + "  ".join(f"{h:>9}" for h in heads) + f"  {'total':>11}  {'bonus':>9}"]
    for sid in students:
        units = [by_unit[(sid, nb)] for nb in notebooks]
        cells = [f"{u['score']:g}/{u['max_score']:g}" for u in units]
        regular = [u for u in units if u["notebook"] not in bonus_notebooks]
        extra = [u for u in units if u["notebook"] in bonus_notebooks]
        total = f"{sum(u['score'] for u in regular):g}/{sum(u['max_score'] for u in regular):g}"
        bonus = f"+{sum(u['score'] for u in extra):g}" if extra else "-"
        lines.append(f"{sid:<{width}}  " + "  ".join(f"{c:>9}" for c in cells) + f"  {total:>11}  {bonus:>9}")
    if any(nb in bonus_notebooks for nb in notebooks):
        lines.append("(+ marks a bonus notebook: its points are extra credit, outside the total)")
    return "\n".join(lines)


def notebook_stats(results: list[dict], notebooks: list[str]) -> str:
    """Per notebook: students, mean, median, full marks, zero, and rows not graded normally, as aligned text."""
    bonus_notebooks = _bonus_notebooks(results)
    lines = [f"{'notebook':<22} {'max':>5} {'mean':>6} {'median':>6} {'full':>5} {'zero':>5}  not graded"]
    for nb in notebooks:
        units = [r for r in results if r["notebook"] == nb]
        scores = [r["score"] for r in units]
        top = max((r["max_score"] for r in units), default=0)
        odd = {}
        for r in units:
            if r["status"] not in ("graded", "graded-with-incidents"):
                odd[r["status"]] = odd.get(r["status"], 0) + 1
        lines.append(
            f"{nb + (' +' if nb in bonus_notebooks else ''):<22} {top:>5g} {statistics.fmean(scores):>6.2f} {statistics.median(scores):>6.2f} "
            f"{sum(s >= top > 0 for s in scores):>5} {sum(s == 0 for s in scores):>5}  "
            + (", ".join(f"{n} {s}" for s, n in sorted(odd.items())) or "-")
        )
    return "\n".join(lines)


def class_summary(results: list[dict]) -> str:
    """What ``deformlab grade`` prints at the end: the per-student table (small classes) and per-notebook statistics."""
    if not results:
        return "no notebooks were graded"
    students = sorted({r["student_id"] for r in results})
    notebooks = sorted({r["notebook"] for r in results})
    parts = []
    if len(students) <= MAX_STUDENT_ROWS:
        parts += [score_table(results, students, notebooks), ""]
    parts.append(notebook_stats(results, notebooks))
    banned = policy_lines(results)
    if banned:
        parts += ["", *banned]
    return "\n".join(parts)


def late_students(rows: list[dict]) -> list[dict]:
    """Per late student of a ``grades.csv`` (its rows as dicts): hours late, late days spent on this assignment, total penalty.

    Rows without the late columns (no due date was applied) are on time.
    """
    late: dict[str, dict] = {}
    for row in rows:
        seconds = float(row.get("seconds_late") or 0)
        if seconds <= 0:
            continue
        entry = late.setdefault(row["student_id"], {"student_id": row["student_id"], "hours_late": round(seconds / 3600, 2),
                                                    "late_days": int(row.get("late_days") or 0), "late_penalty": 0.0})
        entry["late_penalty"] = round(entry["late_penalty"] + float(row.get("late_penalty") or 0), 4)
    return sorted(late.values(), key=lambda e: (-e["hours_late"], e["student_id"]))


def policy_lines(results: list[dict]) -> list[str]:
    """One line per function and routine the library policy forbids there that students called (the report lists who)."""
    rows = policy_violations(results)
    return [f"library policy: {r['function']} called {r['routine']} in {r['students']} notebook(s), scored 0" for r in rows]


def policy_violations(results: list[dict]) -> list[dict]:
    """Per function and library routine the course's policy forbids there: the students whose function called it.

    Only the policy's own routine names are counted (``starter/library_policy.py``).
    """
    found: dict[tuple, set] = defaultdict(set)
    for r in results:
        for t in r.get("tests", []):
            allowed = set(forbidden(t["function"])) if t.get("function") in OWN else set()
            for routine in t.get("policy_violations") or []:
                if routine in allowed:
                    found[(r["notebook"], t["function"], routine)].add(r["student_id"])
    return [
        {"notebook": nb, "function": fn, "routine": routine, "students": len(ids), "student_ids": " ".join(sorted(ids))}
        for (nb, fn, routine), ids in sorted(found.items())
    ]
