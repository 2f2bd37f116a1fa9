"""Per-notebook feedback as one self-contained HTML page, with pictures.

The page is rendered from ``grader/templates/feedback.html.j2`` with Jinja2's
autoescaping on: everything a student's kernel produced (messages, labels,
their id) is text on that page, never markup. Pictures are drawn here, in the
grading process, from the student's collected outputs and the reference's
outputs on the same hidden input: the student's deformation beside the
reference's, both energy curves, both weight fields; beside the first, an
interactive view of the same case (``grader/pipeline/feedback_view.py``).
"""

from __future__ import annotations

import base64
import functools
import io
from pathlib import Path

import nbformat
import numpy as np

from grader.course_pack import is_bonus, pack
from grader.pipeline import feedback_view
from grader.pipeline.verify import graded_cells, hidden_cases

TEMPLATES = Path(__file__).resolve().parent.parent / "templates"


@functools.cache
def template(name: str):
    """A Jinja2 template of ``grader/templates``, HTML-escaping every value."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), autoescape=True, undefined=jinja2.StrictUndefined)
    return env.get_template(name)


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode()


def _draw_mesh(ax, V: np.ndarray, F: np.ndarray, values: np.ndarray | None = None, title: str = "", label: str = "") -> None:
    if V.shape[1] == 2:
        if values is None:
            ax.triplot(V[:, 0], V[:, 1], F, lw=0.4, color="0.3")
        else:
            tpc = ax.tripcolor(V[:, 0], V[:, 1], F, values, shading="gouraud", cmap="coolwarm", vmin=-0.2, vmax=1.2)
            ax.figure.colorbar(tpc, ax=ax, shrink=0.75, label=label)
        ax.set_aspect("equal")
    else:
        ax.plot_trisurf(V[:, 0], V[:, 1], V[:, 2], triangles=F, color="lightsteelblue", edgecolor="0.4", linewidth=0.1)
        lo, hi = V.min(axis=0), V.max(axis=0)
        ax.set_box_aspect(np.maximum(hi - lo, 1e-9))
    ax.set_title(title, fontsize=12)
    ax.set_axis_off()


def pair_figure(V_got, V_ref, F, values_got=None, values_ref=None, titles=("yours", "reference"), label=""):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kw = {"projection": "3d"} if V_got.shape[1] == 3 else {}
    fig = plt.figure(figsize=(10, 4.5))
    for k, (V, vals, title) in enumerate(((V_got, values_got, titles[0]), (V_ref, values_ref, titles[1]))):
        _draw_mesh(fig.add_subplot(1, 2, k + 1, **kw), V, F, vals, title, label)
    return fig


def picture(caption: str, alt: str, fig) -> dict:
    return {"caption": caption, "alt": alt, "png": _png(fig)}


def _pictures(assignment: str | None, function: str, seed: int, collected, result=None) -> list[dict]:
    """Pictures (caption, alt text, base64 PNG, maybe an interactive view) of one hidden case of a function
    the course pack pictures, a failed case first when ``result`` (its FunctionResult) says which failed.

    The pack's ``pictures`` module declares ``PICTURED`` (function names) and
    ``pictures(function, case, value, expected)``, which draws with :func:`pair_figure`,
    :func:`picture` and ``grader.pipeline.feedback_view``; a case it cannot draw is skipped.
    """
    drawer = pack(assignment).pictures_module()
    if drawer is None or function not in getattr(drawer, "PICTURED", ()) or collected is None:
        return []
    import matplotlib

    matplotlib.use("Agg")
    cases, expected = hidden_cases(function, seed, assignment)
    failed = [not c.passed for c in result.cases] if result is not None and len(result.cases) == len(cases) else [False] * len(cases)
    # A picture of a passing case (the same as the reference's to 1e-15) shows the student nothing.
    for _, case, out, ref in sorted(zip(failed, cases, collected.cases, expected), key=lambda row: not row[0]):
        if out.error is not None:
            continue
        try:
            pics = drawer.pictures(function, case, out.value, ref)
        except Exception:  # noqa: BLE001 - a picture of malformed output is not worth failing feedback for
            continue
        if pics:
            return pics
    return []


def _case_message(case) -> str:
    if case.passed:
        return "passed"
    return case.error or "; ".join(f"{v.name}: {v.detail}" for v in case.verdicts if not v.passed)


def feedback_html(spec, results: list, notes: list[str]) -> str:
    """The feedback page of one student × notebook.

    Parameters
    ----------
    spec : UnitSpec
    results : list of (GradedCell, FunctionResult, Collected or None)
        Empty when the notebook was not graded (missing, invalid, grader error): the
        page still shows the notebook's maximum, read from the source notebook.
    notes : list of str
        Repairs, cell errors and incidents, shown above the table.

    Notes
    -----
    The page keeps a ``<!-- late -->`` mark below the score, where
    ``grader.late_policy`` puts the late line once a due date is applied, and
    ``<!-- manual -->…<!-- /manual -->`` around the hand-graded points, which
    ``grader.exports.nbgrader_feedback`` replaces with the TA's grades.
    """
    source = nbformat.reads(spec.source, as_version=4)
    max_score = sum(cell.points for cell in graded_cells(source))
    manual = [
        ((c.metadata.get("nbgrader") or {}).get("grade_id", ""), float((c.metadata.get("nbgrader") or {}).get("points") or 0))
        for c in source.cells
        if c.cell_type == "markdown" and (c.metadata.get("nbgrader") or {}).get("grade")
    ]
    functions = [
        {
            "function": cell.function,
            "score": cell.points * r.fraction,
            "points": cell.points,
            "full": r.fraction == 1.0,
            "summary": r.summary(),
            "cases": [{"label": c.label, "passed": c.passed, "message": _case_message(c)} for c in r.cases],
        }
        for cell, r, _ in results
    ]
    pictures = [p for cell, r, collected in results for p in _pictures(spec.assignment, cell.function, spec.seed, collected, r)]
    return template("feedback.html.j2").render(
        student_id=spec.student_id,
        notebook=spec.notebook,
        seed=spec.seed,
        score=sum(f["score"] for f in functions),
        max_score=max_score,
        bonus=is_bonus(pack(spec.assignment).name, spec.notebook),
        manual_points=sum(points for _, points in manual),
        manual_cells=[gid for gid, _ in manual],
        # A missing or unreadable notebook has no written answers for a TA to read.
        handed_in=spec.submission is not None and not spec.submission_error,
        notes=notes,
        functions=functions,
        pictures=pictures,
        **feedback_view.page_context(pictures),
    )
