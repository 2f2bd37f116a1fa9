"""Per-notebook feedback as one self-contained HTML page, with pictures.

Pictures are drawn here, in the grading process, from the student's collected
outputs and the reference's outputs on the same hidden input: the student's
deformation beside the reference's, both energy curves, both weight fields.
"""

from __future__ import annotations

import base64
import html
import io
import numpy as np

from grader.pipeline.verify import hidden_cases

PICTURED = ("arap_solve", "laplacian_editing", "bbw", "unconstrained_biharmonic_weights")


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80, bbox_inches="tight")
    import matplotlib.pyplot as plt

    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode()


def _draw_mesh(ax, V: np.ndarray, F: np.ndarray, values: np.ndarray | None = None, title: str = "") -> None:
    if V.shape[1] == 2:
        if values is None:
            ax.triplot(V[:, 0], V[:, 1], F, lw=0.3, color="0.3")
        else:
            tpc = ax.tripcolor(V[:, 0], V[:, 1], F, values, shading="gouraud", cmap="coolwarm", vmin=-0.2, vmax=1.2)
            ax.figure.colorbar(tpc, ax=ax, shrink=0.7)
        ax.set_aspect("equal")
    else:
        ax.plot_trisurf(V[:, 0], V[:, 1], V[:, 2], triangles=F, color="lightsteelblue", edgecolor="0.4", linewidth=0.1)
        lo, hi = V.min(axis=0), V.max(axis=0)
        ax.set_box_aspect(np.maximum(hi - lo, 1e-9))
    ax.set_title(title, fontsize=9)
    ax.set_axis_off()


def _pair_figure(V_got, V_ref, F, values_got=None, values_ref=None, titles=("yours", "reference")):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kw = {"projection": "3d"} if V_got.shape[1] == 3 else {}
    fig = plt.figure(figsize=(7, 3.2))
    for k, (V, vals, title) in enumerate(((V_got, values_got, titles[0]), (V_ref, values_ref, titles[1]))):
        _draw_mesh(fig.add_subplot(1, 2, k + 1, **kw), V, F, vals, title)
    return fig


def _pictures(function: str, seed: int, collected) -> list[tuple[str, str]]:
    """(caption, base64 PNG) pairs for the first readable case of a pictured function."""
    if function not in PICTURED or collected is None:
        return []
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cases, expected = hidden_cases(function, seed)
    for case, out, ref in zip(cases, collected.cases, expected):
        if out.error is not None:
            continue
        try:
            V, F = np.asarray(case.steps[0].args[0], float), np.asarray(case.steps[0].args[1], int)
            if function == "arap_solve":
                U, energies = np.asarray(out.value[0], float), np.asarray(out.value[1], float).ravel()
                pics = [(f"{case.label}: your deformation beside the reference's", _png(_pair_figure(U, np.asarray(ref[0]), F)))]
                fig, ax = plt.subplots(figsize=(4.5, 3))
                ax.semilogy(np.arange(1, len(energies) + 1), np.maximum(energies, 1e-300), "o-", label="yours")
                ax.semilogy(np.arange(1, len(ref[1]) + 1), np.maximum(np.asarray(ref[1], float), 1e-300), "s--", label="reference")
                ax.set_xlabel("iteration")
                ax.set_ylabel("ARAP energy")
                ax.legend()
                pics.append((f"{case.label}: energy per iteration", _png(fig)))
                return pics
            if function == "laplacian_editing":
                return [(f"{case.label}: your result beside the reference's", _png(_pair_figure(np.asarray(out.value, float), np.asarray(ref), F)))]
            W, W_ref = np.asarray(out.value, float), np.asarray(ref, float)
            if V.shape[1] == 2 and W.shape == W_ref.shape:
                return [(f"{case.label}: weights of handle 1, yours beside the reference's", _png(_pair_figure(V, V, F, W[:, 0], W_ref[:, 0])))]
        except Exception:  # noqa: BLE001 - a picture of malformed output is not worth failing feedback for
            continue
    return []


def feedback_html(spec, results: list, notes: list[str]) -> str:
    """The feedback page of one student × notebook.

    Parameters
    ----------
    spec : UnitSpec
    results : list of (GradedCell, FunctionResult, Collected or None)
    notes : list of str
        Repairs, cell errors and incidents, shown above the table.
    """
    esc = html.escape
    total = sum(cell.points * r.fraction for cell, r, _ in results)
    max_total = sum(cell.points for cell, _, _ in results)
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{esc(spec.student_id)} · {esc(spec.notebook)}</title>",
        "<style>body{font-family:sans-serif;max-width:60em;margin:2em auto}table{border-collapse:collapse}"
        "td,th{border:1px solid #ccc;padding:4px 8px;vertical-align:top}.ok{color:#080}.bad{color:#b00}"
        "img{max-width:100%}</style></head><body>",
        f"<h1>{esc(spec.notebook)} — {esc(spec.student_id)}</h1>",
        f"<p>Autograded score: <b>{total:.2f} / {max_total:.2f}</b>. Hidden inputs were drawn with seed {spec.seed}.</p>",
    ]
    if notes:
        parts.append("<h2>Notes</h2><ul>" + "".join(f"<li>{esc(n)}</li>" for n in notes) + "</ul>")
    if results:
        parts.append("<h2>Tests</h2><table><tr><th>function</th><th>score</th><th>result</th></tr>")
        for cell, result, _ in results:
            cls = "ok" if result.fraction == 1.0 else "bad"
            rows = "".join(
                f"<li class='{'ok' if c.passed else 'bad'}'>{esc(c.label)}: "
                + ("passed" if c.passed else esc(c.error or "; ".join(f"{v.name}: {v.detail}" for v in c.verdicts if not v.passed)))
                + "</li>"
                for c in result.cases
            )
            parts.append(
                f"<tr><td><code>{esc(cell.function)}</code></td><td class='{cls}'>{cell.points * result.fraction:.2f} / {cell.points:g}</td>"
                f"<td>{esc(result.summary())}<ul>{rows}</ul></td></tr>"
            )
        parts.append("</table>")
        pictures = [p for cell, _, collected in results for p in _pictures(cell.function, spec.seed, collected)]
        if pictures:
            parts.append("<h2>Pictures</h2>")
            parts.extend(f"<figure><img src='data:image/png;base64,{b64}'><figcaption>{esc(cap)}</figcaption></figure>" for cap, b64 in pictures)
    parts.append("</body></html>")
    return "\n".join(parts)
