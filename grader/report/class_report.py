"""The class report: one offline HTML page with plots, and the same numbers as CSV (``deformlab report OUT``).

Everything is read back from a grading run's output folder: ``grades.csv`` names
the rows, ``units/<student>/<notebook>.json`` holds each row's per-case verdicts,
times and incidents. Plots are PNGs inside the page (no script, no CDN), and
everything that came from a student (ids, messages) is escaped by the template.
"""

from __future__ import annotations

import re
import statistics
from collections import Counter, defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from grader.course_pack import is_bonus
from grader.report.scores import late_students, policy_violations
from grader.pipeline import record
from grader.spreadsheet import csv_text, read_csv
from grader.pipeline.feedback import _png, template

GRADED = ("graded", "graded-with-incidents")


def load_results(out: Path) -> list[dict]:
    """The unit results of a run, one per ``grades.csv`` row.

    Raises
    ------
    FileNotFoundError
        If ``out`` holds no ``grades.csv`` (not a grading output folder).
    """
    out = Path(out)
    grades = out / "grades.csv"
    if not grades.is_file():
        raise FileNotFoundError(f"{out} is not the output folder of a grading run: it has no grades.csv")
    results = []
    for row in read_csv(grades):
        unit = record.load_unit(out, row["student_id"], row["notebook"])
        if unit is None:  # grades.csv without its unit file: keep the row's numbers, no details
            unit = {"student_id": row["student_id"], "notebook": row["notebook"], "status": "unknown", "tests": [],
                    "score": float(row["score"]), "max_score": float(row["max_score"]), "reasons": []}
        results.append(unit)
    return results


def anonymize(text: str, student_ids: list[str]) -> str:
    """``text`` with every student id replaced by ``<student>`` (longest first, so no id leaks in part)."""
    for sid in sorted(student_ids, key=len, reverse=True):
        if len(sid) >= 3:
            text = re.sub(re.escape(sid), "<student>", text, flags=re.IGNORECASE)
    return text


@dataclass
class ClassReport:
    """The report's numbers; each table is also one CSV file."""

    notebooks: list[dict] = field(default_factory=list)
    functions: list[dict] = field(default_factory=list)
    cases: list[dict] = field(default_factory=list)
    resources: list[dict] = field(default_factory=list)
    incidents: list[dict] = field(default_factory=list)
    late: list[dict] = field(default_factory=list)
    policy: list[dict] = field(default_factory=list)
    n_students: int = 0


def summarize(results: list[dict], top_cases: int = 20) -> ClassReport:
    """Per-notebook and per-function scores, the hidden cases failed most, resources, incidents."""
    students = sorted({r["student_id"] for r in results})
    report = ClassReport(n_students=len(students))
    for nb in sorted({r["notebook"] for r in results}):
        units = [r for r in results if r["notebook"] == nb]
        scores = [float(r["score"]) for r in units]
        top = max(float(r["max_score"]) for r in units)
        status = Counter(r["status"] for r in units)
        execution = [r["execution_s"] for r in units if r.get("execution_s") is not None]
        rss = [r["peak_rss_bytes"] / 2**20 for r in units if r.get("peak_rss_bytes")]
        report.notebooks.append({
            "notebook": nb, "bonus": is_bonus(units[0].get("assignment"), nb), "students": len(units), "max_score": top,
            "mean": round(statistics.fmean(scores), 3), "median": statistics.median(scores),
            "full_marks": sum(s >= top > 0 for s in scores), "zero": sum(s == 0 for s in scores),
            "graded": sum(status[s] for s in GRADED), "missing": status["missing"], "invalid": status["invalid"],
            "grader_error": status["grader-error"], "with_incidents": status["graded-with-incidents"],
        })
        report.resources.append({
            "notebook": nb,
            "execution_s_median": round(statistics.median(execution), 2) if execution else None,
            "execution_s_max": round(max(execution), 2) if execution else None,
            "peak_rss_mib_median": round(statistics.median(rss), 1) if rss else None,
            "peak_rss_mib_max": round(max(rss), 1) if rss else None,
        })
    by_function: dict[tuple, list] = defaultdict(list)
    failures: dict[tuple, list] = defaultdict(list)
    for r in results:
        for t in r.get("tests", []):
            by_function[(r["notebook"], t["function"])].append((r, t))
            if r["status"] not in GRADED:
                continue
            for c in t.get("cases", []):
                # A function left as the release stub raises NotImplementedError on every case: unattempted, not failed.
                if not c["passed"] and not (c.get("error") or "").startswith("NotImplementedError"):
                    failures[(t["function"], c["label"])].append((r["student_id"], c.get("error") or "; ".join(c.get("failed", []))))
    for (nb, fn), rows in sorted(by_function.items()):
        fractions = [t["score"] / t["points"] if t["points"] else 0.0 for _, t in rows]
        submitted = [f for (r, _), f in zip(rows, fractions) if r["status"] in GRADED]
        report.functions.append({
            "notebook": nb, "function": fn, "points": rows[0][1]["points"], "students": len(rows),
            "mean_fraction": round(statistics.fmean(fractions), 3),
            "full": sum(f == 1.0 for f in fractions), "partial": sum(0 < f < 1 for f in fractions),
            "zero": sum(f == 0 for f in fractions), "zero_among_graded": sum(f == 0 for f in submitted),
        })
    ranked = sorted(failures.items(), key=lambda kv: (-len(kv[1]), kv[0]))[:top_cases]
    for (fn, label), fails in ranked:
        messages = Counter(msg for _, msg in fails)
        example, _ = messages.most_common(1)[0]
        report.cases.append({
            "function": fn, "case": label, "students_failed": len({s for s, _ in fails}),
            "example_message": anonymize(example, students)[:600], "distinct_messages": len(messages),
        })
    report.policy = policy_violations(results)
    for r in results:
        if r["status"] in ("graded-with-incidents", "grader-error", "invalid"):
            report.incidents.append({
                "student_id": r["student_id"], "notebook": r["notebook"], "status": r["status"],
                "what": "; ".join(str(x) for x in (r.get("events") or []) + (r.get("reasons") or []))[:600],
            })
    return report


def _figures(report: ClassReport, results: list[dict]) -> list[dict]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pictures = []
    notebooks = [n["notebook"] for n in report.notebooks]
    cols = min(4, len(notebooks))
    rows = -(-len(notebooks) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3 * rows), squeeze=False)
    for ax, nb in zip(axes.ravel(), report.notebooks):
        scores = [float(r["score"]) for r in results if r["notebook"] == nb["notebook"]]
        ax.hist(scores, bins=np.linspace(0, max(nb["max_score"], 1), 11), color="#4a7ab5", edgecolor="white")
        ax.set_title(nb["notebook"] + (" (bonus)" if nb["bonus"] else ""), fontsize=10)
        ax.set_xlabel(f"score (of {nb['max_score']:g})")
        ax.set_ylabel("students")
    for ax in axes.ravel()[len(notebooks):]:
        ax.set_axis_off()
    fig.tight_layout()
    pictures.append({"id": "scores-per-notebook", "caption": "Score histogram per notebook.",
                     "alt": "Histograms of the students' scores, one per notebook.", "png": _png(fig)})

    fns = report.functions
    fig, ax = plt.subplots(figsize=(9, 0.28 * len(fns) + 1.2))
    y = np.arange(len(fns))[::-1]
    left = np.zeros(len(fns))
    for key, colour, label in (("full", "#2e8b57", "full points"), ("partial", "#e0a030", "partial"), ("zero", "#c0392b", "zero")):
        vals = np.array([f[key] for f in fns], float)
        ax.barh(y, vals, left=left, color=colour, label=label)
        left += vals
    ax.set_yticks(y, [f"{f['notebook'][:2]} {f['function']}" for f in fns], fontsize=8)
    ax.set_xlabel("students")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_title("Points per function: how many students earned all, part or none")
    fig.tight_layout()
    pictures.append({"id": "scores-per-function", "caption": "Per function: students with full, partial and zero points.",
                     "alt": "Stacked horizontal bars, one per function, of students with full, partial and zero points.", "png": _png(fig)})

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.8))
    for ax, key, scale, label in ((a1, "execution_s", 1, "execution time (s)"), (a2, "peak_rss_bytes", 2**20, "peak memory (MiB)")):
        data = [[r[key] / scale for r in results if r["notebook"] == nb and r.get(key)] for nb in notebooks]
        shown = [(nb, d) for nb, d in zip(notebooks, data) if d]
        if shown:
            ax.boxplot([d for _, d in shown])
            ax.set_xticks(range(1, len(shown) + 1), [nb for nb, _ in shown], rotation=30, ha="right", fontsize=8)
        ax.set_xlabel("notebook")
        ax.set_ylabel(label)
        ax.set_title(label + " per notebook")
    fig.tight_layout()
    pictures.append({"id": "resources", "caption": "Execution time and peak memory of the students' kernels, per notebook.",
                     "alt": "Box plots of execution time and of peak memory per notebook.", "png": _png(fig)})
    return pictures


CSV_TABLES = ("notebooks", "functions", "cases", "resources", "incidents", "late", "policy")
HEADERS = {
    "notebooks": ["notebook", "bonus", "students", "max_score", "mean", "median", "full_marks", "zero", "graded", "missing",
                  "invalid", "grader_error", "with_incidents"],
    "functions": ["notebook", "function", "points", "students", "mean_fraction", "full", "partial", "zero", "zero_among_graded"],
    "cases": ["function", "case", "students_failed", "distinct_messages", "example_message"],
    "resources": ["notebook", "execution_s_median", "execution_s_max", "peak_rss_mib_median", "peak_rss_mib_max"],
    "incidents": ["student_id", "notebook", "status", "what"],
    "late": ["student_id", "hours_late", "late_days", "late_penalty"],
    "policy": ["notebook", "function", "routine", "students", "student_ids"],
}


def collusion_of_run(out: Path, submitted: Path, assignment: str, sources: list[Path]):
    """Collusion evidence of the run in ``out``, from a child process under limits (``grader.report.collusion``).

    Returns
    -------
    grader.report.collusion.CollusionEvidence
        Ranked pairs and the cuts of oversized code; or none and the reason, if the pass failed or hit a limit.
    """
    from grader.report.collusion import limited_collusion

    return limited_collusion(load_results(out), submitted, sources, assignment)


def write_class_report(out: Path, target: Path | None = None, collusion=None) -> Path:
    """Write ``report/index.html`` and one CSV per table; returns the page's path.

    Parameters
    ----------
    out : Path
        A grading run's output folder.
    target : Path, optional
        Where the report goes (default: ``out/report``).
    collusion : grader.report.collusion.CollusionEvidence, optional
        Ranked pairs to show side by side, the cuts of oversized code, or why the pass produced nothing;
        ``None`` when the submissions were not compared.
    """
    out = Path(out)
    target = Path(target) if target else out / "report"
    results = load_results(out)
    report = summarize(results)
    report.late = late_students(read_csv(out / "grades.csv"))
    for name in CSV_TABLES:
        record.write_text_atomic(target / f"{name}.csv", csv_text(HEADERS[name], getattr(report, name)))
    page = template("report.html.j2").render(
        report=report, pictures=_figures(report, results), csv_tables=CSV_TABLES, collusion=collusion,
        seeds=sorted({r.get("seed") for r in results if r.get("seed") is not None}),
    )
    path = target / "index.html"
    record.write_text_atomic(path, page)
    return path
