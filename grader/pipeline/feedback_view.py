"""The interactive 3D view of a feedback page: numbers for the viewer and a description for screen readers.

A view shows the student's result beside the reference's on one hidden case:
two canvases whose cameras move together, per-vertex difference (or a weight
field) as colour with a labeled scale, the handles marked. Everything it draws
comes from :func:`deformation_view` or :func:`weights_view` as numbers only:
vertex positions quantized to integers, faces and handles as vertex indices,
colour levels as integers, colour maps as numbers. No string a student's kernel
produced reaches the page; a student output that is not a finite numeric array
of the case's shape gets no view, only a fixed sentence saying so.

The viewer itself, ``grader/templates/feedback_view.js``, is a few hundred lines
of canvas 2D, inlined once per page that has a view, and allowed to run by the
page's Content-Security-Policy through its hash alone; that policy forbids every
connection and every load from outside the page (:func:`page_context`).
"""

from __future__ import annotations

import base64
import functools
import hashlib
from collections import Counter
from pathlib import Path

import numpy as np
from markupsafe import Markup

from grader.checks.base import ShapeError, as_array

#: Largest mesh shown; beyond it the page says so and keeps only the static picture.
VERTEX_BUDGET = 5000
FACE_BUDGET = 10000
#: Quantization: positions are integers, QUANT steps per half-extent of the reference's bounding box.
QUANT = 4096
#: A student vertex farther than this many half-extents from the reference's centre is drawn at that distance.
FAR = 8.0
#: Colour fields are integers 0..LEVELS over their scale.
LEVELS = 1000
#: A vertex "differs" when it is off by more than this share of the reference's bounding-box diagonal.
POSITION_SHARE = 0.01
#: A weight "differs" from the reference's by more than this.
WEIGHT_TOL = 0.01

# Colour maps as (t, r, g, b) stops, t in [0, 1] along the scale.
DIFFERENCE_STOPS = ((0.0, 222, 230, 242), (0.25, 253, 219, 110), (0.5, 247, 140, 60), (0.75, 214, 47, 39), (1.0, 103, 0, 61))

VIEWER_JS = (Path(__file__).resolve().parent.parent / "templates" / "feedback_view.js").read_text()
if "</" in VIEWER_JS or "<!--" in VIEWER_JS:  # the script is inlined in a <script> element
    raise RuntimeError("feedback_view.js must not contain '</' or '<!--'")


@functools.cache
def _script_hash() -> str:
    return base64.b64encode(hashlib.sha256(VIEWER_JS.encode()).digest()).decode()


def csp() -> str:
    """The page's Content-Security-Policy: no connection, no load from outside, only the viewer's own script."""
    return (
        "default-src 'none'; connect-src 'none'; img-src data:; style-src 'unsafe-inline'; "
        f"script-src 'sha256-{_script_hash()}'; base-uri 'none'; form-action 'none'"
    )


def page_context(pictures: list[dict]) -> dict:
    """What the feedback template needs for its views: ``csp``, and ``viewer_js`` once if any picture has a view.

    Numbers each view (``view["id"]``) so that the page's element ids are unique.
    """
    views = [p["view"] for p in pictures if p.get("view")]
    for k, view in enumerate(views):
        view["id"] = k
    return {"csp": csp(), "viewer_js": Markup(VIEWER_JS) if any("data" in v for v in views) else ""}


def _too_large(V: np.ndarray, F: np.ndarray) -> dict | None:
    if len(V) <= VERTEX_BUDGET and len(F) <= FACE_BUDGET:
        return None
    return {"skipped": f"This mesh has {len(V):,} vertices and {len(F):,} triangles, more than the interactive view shows "
                       f"({VERTEX_BUDGET:,} vertices, {FACE_BUDGET:,} triangles); the picture above shows it whole."}


def student_array(value, shape: tuple[int, int]) -> np.ndarray | None:
    """The student's output as a finite real array of ``shape``, or None (strings, NaN, complex, wrong shape...)."""
    if isinstance(value, np.ndarray) and value.dtype.kind not in "biuf":
        return None
    try:
        return as_array(value, shape)
    except (ShapeError, ValueError, TypeError, OverflowError, MemoryError):
        return None


def _unreadable(shape: tuple[int, int]) -> dict:
    return {"skipped": f"No interactive view: your output is not a finite numeric array of shape ({shape[0]}, {shape[1]})."}


def _frame(reference: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre and half-extent of the reference's bounding box."""
    lo, hi = reference.min(axis=0), reference.max(axis=0)
    return (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-300)


def _quantized(P: np.ndarray, centre: np.ndarray, half: float) -> tuple[list[int], int]:
    """Positions as integers (QUANT per half-extent, flattened) and how many had to be pulled in to FAR."""
    X = (P - centre) / half
    far = int(np.count_nonzero(np.abs(X).max(axis=1) > FAR))
    return np.rint(np.clip(X, -FAR, FAR) * QUANT).astype(np.int64).ravel().tolist(), far


def _levels(values: np.ndarray, lo: float, hi: float) -> list[int]:
    t = (values - lo) / (hi - lo) if hi > lo else np.zeros_like(values)
    return np.rint(np.clip(t, 0.0, 1.0) * LEVELS).astype(np.int64).tolist()


def _stops(stops) -> list[list[float]]:
    return [[round(float(t), 4), int(r), int(g), int(b)] for t, r, g, b in stops]


def _legend(label: str, stops, lo: float, hi: float, ticks: int = 5) -> dict:
    """A scale for the template: its label, a CSS gradient and tick texts, all built here from numbers."""
    gradient = ", ".join(f"rgb({int(r)}, {int(g)}, {int(b)}) {100 * t:.1f}%" for t, r, g, b in stops)
    return {
        "label": label,
        "gradient": f"linear-gradient(to right, {gradient})",
        "ticks": [{"pos": round(100 * k / (ticks - 1), 1), "text": f"{lo + (hi - lo) * k / (ticks - 1):.3g}"} for k in range(ticks)],
    }


def _nearest_handle(points: np.ndarray, V: np.ndarray, groups: list[np.ndarray]) -> np.ndarray:
    """For each point, the index of the handle (group of vertices) with the nearest vertex in the rest mesh ``V``."""
    members = np.concatenate(groups)
    owner = np.concatenate([np.full(len(g), j) for j, g in enumerate(groups)])
    distance = np.linalg.norm(points[:, None, :] - V[members][None, :, :], axis=2)
    return owner[np.argmin(distance, axis=1)]


def _signed_areas(P: np.ndarray, F: np.ndarray) -> np.ndarray:
    a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def _normals(P: np.ndarray, F: np.ndarray) -> np.ndarray:
    return np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])


def inverted_triangles(V: np.ndarray, U: np.ndarray, F: np.ndarray, U_ref: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Triangles of ``U`` turned over, and those of ``U_ref``.

    In 2D a triangle is inverted when its signed area has the opposite sign to the rest mesh ``V``'s
    (meshes may mix orientations); on a surface in 3D, when its normal points away from the reference's.

    Returns
    -------
    (k,) int, (k_ref,) int
        Indices into ``F``.
    """
    if V.shape[1] == 2:
        rest = np.sign(_signed_areas(V, F))
        return (np.flatnonzero(np.sign(_signed_areas(U, F)) * rest < 0),
                np.flatnonzero(np.sign(_signed_areas(U_ref, F)) * rest < 0))
    facing = np.einsum("ij,ij->i", _normals(U, F), _normals(U_ref, F))
    return np.flatnonzero(facing < 0), np.zeros(0, np.int64)


def _count(k: int, singular: str, plural: str | None = None) -> str:
    return f"{k} {singular if k == 1 else plural or singular + 's'}"


def _handle(handles: np.ndarray, j: int) -> str:
    return f"handle {j + 1} (vertex {int(handles[j])})"


def deformation_view(V: np.ndarray, F: np.ndarray, handles: np.ndarray, got, U_ref: np.ndarray) -> dict:
    """The view of a deformed mesh: the student's ``got`` beside ``U_ref``, coloured by the distance between them.

    Parameters
    ----------
    V : (n, d) float
        Rest positions (d = 2 or 3), grader-side.
    F : (m, 3) int
    handles : (k,) int
        Handle vertices; handle ``j + 1`` on the page is ``handles[j]``.
    got : Any
        The student's deformed positions, hostile: anything but a finite (n, d) array gets no view.
    U_ref : (n, d) float
        The reference's.

    Returns
    -------
    dict
        ``{"skipped": sentence}``, or ``{"data": numbers for the viewer, "description": str, "fields": [legend],
        "notes": [str]}``.
    """
    if (skipped := _too_large(V, F)) is not None:
        return skipped
    n, d = V.shape
    U = student_array(got, (n, d))
    if U is None:
        return _unreadable((n, d))
    distance = np.linalg.norm(U - U_ref, axis=1)
    diagonal = float(np.linalg.norm(U_ref.max(axis=0) - U_ref.min(axis=0)))
    worst = int(np.argmax(distance))
    largest = float(distance[worst])
    groups = [np.array([h]) for h in handles]
    hi = largest if largest > 0 else 1.0
    centre, half = _frame(U_ref)
    positions, far = _quantized(U, centre, half)
    reference_positions, _ = _quantized(U_ref, centre, half)
    levels = _levels(distance, 0.0, hi)

    sentences = []
    if largest == 0:
        sentences.append("Your result equals the reference's at every vertex.")
    else:
        off = int(np.count_nonzero(distance > POSITION_SHARE * diagonal))
        near = f", nearest {_handle(handles, int(_nearest_handle(V[[worst]], V, groups)[0]))}" if len(handles) else ""
        sentences.append(
            f"Largest difference from the reference's position: {largest:.3g} at vertex {worst}{near}; "
            f"the reference's result is {diagonal:.3g} across its bounding box, and "
            f"{_count(off, 'vertex', 'vertices')} of {n} {'is' if off == 1 else 'are'} off by more than "
            f"{100 * POSITION_SHARE:g}% of that."
        )
    inverted, inverted_ref = inverted_triangles(V, U, F, U_ref)
    what = "inverted" if d == 2 else "facing the opposite way from the reference's"
    text = f"{_count(len(inverted), 'triangle')} {what}"
    if len(inverted) and len(handles):
        counts = Counter(_nearest_handle(V[F[inverted]].mean(axis=1), V, groups).tolist())
        (j, most), = counts.most_common(1)
        text += f" near {_handle(handles, j)}" if most == len(inverted) else f", {most} of them near {_handle(handles, j)}"
    sentences.append(text + (f"; the reference's result has {len(inverted_ref)}." if d == 2 else "."))
    notes = [f"{far} of your vertices lie more than {FAR:g} half-widths of the reference's result from its centre; "
             "they are drawn at that distance."] if far else []
    return {
        "data": {
            "d": d, "q": QUANT, "l": LEVELS, "f": F.astype(np.int64).ravel().tolist(),
            "p": [positions, reference_positions],
            "c": [[levels, levels]],
            "m": [_stops(DIFFERENCE_STOPS)],
            "h": [g.tolist() for g in groups],
            "w": worst,
        },
        "description": " ".join(sentences),
        "fields": [_legend("distance between your vertex and the reference's", DIFFERENCE_STOPS, 0.0, hi)],
        "notes": notes,
    }


def _weight_stops(lo: float, hi: float) -> tuple:
    """Blue at 0, red at 1, darker outside [0, 1], as stops over [lo, hi] (lo < 0, hi > 1)."""
    t = lambda w: (w - lo) / (hi - lo)  # noqa: E731
    return ((0.0, 16, 24, 96), (t(0.0), 59, 76, 192), (t(0.5), 221, 221, 221), (t(1.0), 180, 4, 38), (1.0, 80, 0, 16))


def weights_view(V: np.ndarray, F: np.ndarray, groups: list[np.ndarray], got, W_ref: np.ndarray) -> dict:
    """The view of a weight field: the student's ``got`` beside ``W_ref`` on the rest mesh.

    Colours: the largest difference over the handles at each vertex, or the weight of one handle.

    Parameters
    ----------
    V : (n, d) float
    F : (m, 3) int
    groups : list of (k_j,) int
        The vertices of each handle; handle ``j + 1`` on the page is column ``j``.
    got : Any
        The student's weights, hostile: anything but a finite (n, m) array gets no view.
    W_ref : (n, m) float

    Returns
    -------
    dict
        As :func:`deformation_view`.
    """
    if (skipped := _too_large(V, F)) is not None:
        return skipped
    n, m = W_ref.shape
    W = student_array(got, (n, m))
    if W is None:
        return _unreadable((n, m))
    gap = np.abs(W - W_ref)
    worst_vertex, worst_handle = (int(i) for i in np.unravel_index(int(np.argmax(gap)), gap.shape))
    largest = float(gap[worst_vertex, worst_handle])
    per_vertex = gap.max(axis=1)
    sentences = []
    if largest == 0:
        sentences.append("Your weights equal the reference's at every vertex.")
    else:
        off = int(np.count_nonzero(per_vertex > WEIGHT_TOL))
        sentences.append(
            f"Largest difference from the reference's weights: {largest:.3g} at vertex {worst_vertex}, handle {worst_handle + 1} "
            f"(yours {W[worst_vertex, worst_handle]:.3g}, the reference's {W_ref[worst_vertex, worst_handle]:.3g}); "
            f"{off} of {n} vertices {'differs' if off == 1 else 'differ'} by more than {WEIGHT_TOL:g}."
        )
    outside = lambda A: int(np.count_nonzero(np.any((A < -1e-9) | (A > 1 + 1e-9), axis=1)))  # noqa: E731
    unsummed = lambda A: int(np.count_nonzero(np.abs(A.sum(axis=1) - 1) > 1e-6))  # noqa: E731
    sentences.append(f"{_count(outside(W), 'vertex', 'vertices')} with a weight outside [0, 1] (the reference's: {outside(W_ref)}); "
                     f"{_count(unsummed(W), 'vertex', 'vertices')} whose weights do not sum to 1 (the reference's: {unsummed(W_ref)}).")

    centre, half = _frame(V)
    positions, _ = _quantized(V, centre, half)
    hi_gap = largest if largest > 0 else 1.0
    lo, hi = min(-0.2, float(W_ref.min())), max(1.2, float(W_ref.max()))
    weight_stops = _weight_stops(lo, hi)
    gap_levels = _levels(per_vertex, 0.0, hi_gap)
    fields = [_legend("difference from the reference's weights (largest over the handles)", DIFFERENCE_STOPS, 0.0, hi_gap)]
    fields += [_legend(f"weight of handle {j + 1} (darker outside [0, 1])", weight_stops, lo, hi) for j in range(m)]
    out_of_scale = int(np.count_nonzero((W < lo) | (W > hi)))
    notes = [f"{out_of_scale} of your weights lie outside the scale's [{lo:.3g}, {hi:.3g}]; they are drawn in its end colours."] \
        if out_of_scale else []
    return {
        "data": {
            "d": V.shape[1], "q": QUANT, "l": LEVELS, "f": F.astype(np.int64).ravel().tolist(),
            "p": [positions, positions],
            "c": [[gap_levels, gap_levels]] + [[_levels(W[:, j], lo, hi), _levels(W_ref[:, j], lo, hi)] for j in range(m)],
            "m": [_stops(DIFFERENCE_STOPS)] + [_stops(weight_stops)] * m,
            "h": [np.asarray(g, np.int64).tolist() for g in groups],
            "w": worst_vertex,
        },
        "description": " ".join(sentences),
        "fields": fields,
        "notes": notes,
    }
