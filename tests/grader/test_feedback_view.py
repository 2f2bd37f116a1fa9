"""The interactive view of a feedback page: only numbers reach it, its description is right, the page runs only the viewer.

Planted cases on ``starter.shapes`` meshes give descriptions whose numbers are known by construction;
the hidden cases of the pictured functions give the data a real page embeds.
"""

from __future__ import annotations

import base64
import hashlib
import html
import json
import math
import re

import nbformat
import numpy as np
import pytest
import scipy.sparse as sp

from grader.harness.outputs import CaseOutput, Collected
from grader.pipeline import feedback_view
from deformlab_packs.deformation.pictures import PICTURED
from deformlab_packs.deformation.pictures import view as view_for
from grader.pipeline.feedback import feedback_html
from grader.pipeline.feedback_view import FAR, LEVELS, QUANT, VERTEX_BUDGET, deformation_view, weights_view
from grader.pipeline.unit import UnitSpec
from grader.pipeline.verify import GradedCell, hidden_cases, verify
from starter import shapes

SEED = 11
KEYS = {"d", "q", "l", "f", "p", "c", "m", "h", "w"}


def numbers_only(value, path="data") -> list[str]:
    """Every leaf that is not a finite int or float (bools and strings included), by path."""
    if isinstance(value, dict):
        return [f"{path}: key {k!r}" for k in value if k not in KEYS] + [p for k, v in value.items() for p in numbers_only(v, f"{path}.{k}")]
    if isinstance(value, list):
        return [p for k, v in enumerate(value) for p in numbers_only(v, f"{path}[{k}]")]
    if type(value) is int or (type(value) is float and math.isfinite(value)):
        return []
    return [f"{path}: {type(value).__name__} {value!r:.40}"]


def folded_strip(d: int = 2):
    """A 3 x 0.6 strip (10 x 3 cells) whose last two columns of cells are mirrored about x = 2.4, and one left
    boundary vertex pulled 1.5 outwards: 12 triangles inverted, all nearest the right handle; the largest
    difference 1.5 at vertex 1; 9 vertices moved."""
    V, F = shapes.grid_2d(10, 3, width=3.0, height=0.6)
    U = V.copy()
    right = V[:, 0] > 2.4 + 1e-9
    U[right, 0] = 4.8 - V[right, 0]
    U[1, 0] = -1.5
    if d == 3:
        V, U = np.c_[V, np.zeros(len(V))], np.c_[U, np.zeros(len(U))]
    return V, F, np.array([0, 40]), U


def test_a_folded_strip_is_described_with_its_planted_numbers():
    V, F, handles, U = folded_strip()
    view = deformation_view(V, F, handles, U, V.copy())
    assert view["description"] == (
        "Largest difference from the reference's position: 1.5 at vertex 1, nearest handle 1 (vertex 0); "
        "the reference's result is 3.06 across its bounding box, and 9 vertices of 44 are off by more than 1% of that. "
        "12 triangles inverted near handle 2 (vertex 40); the reference's result has 0."
    )
    assert view["data"]["w"] == 1
    assert view["data"]["h"] == [[0], [40]]
    assert view["fields"][0]["ticks"][-1]["text"] == "1.5"


def test_a_folded_surface_in_3d_counts_triangles_facing_away_from_the_reference():
    V, F, handles, U = folded_strip(d=3)
    view = deformation_view(V, F, handles, U, V.copy())
    assert "12 triangles facing the opposite way from the reference's near handle 2 (vertex 40)." in view["description"]
    assert view["data"]["d"] == 3 and len(view["data"]["p"][0]) == 3 * len(V)


def test_triangles_the_reference_inverts_too_are_counted_on_both_sides():
    V, F, handles, U = folded_strip()
    view = deformation_view(V, F, handles, U, U.copy())
    assert view["description"].startswith("Your result equals the reference's at every vertex.")
    assert view["description"].endswith("12 triangles inverted near handle 2 (vertex 40); the reference's result has 12.")


def test_weights_are_described_with_their_planted_numbers():
    V, F = shapes.grid_2d(10, 3, width=3.0, height=0.6)
    W_ref = np.c_[1 - V[:, 0] / 3.0, V[:, 0] / 3.0]
    W = W_ref.copy()
    k = 8 * 4 + 2  # x = 2.4: the reference's weight of handle 2 is 0.8
    W[k, 1] += 0.31
    view = weights_view(V, F, [np.array([0]), np.array([40])], W, W_ref)
    assert view["description"] == (
        f"Largest difference from the reference's weights: 0.31 at vertex {k}, handle 2 (yours 1.11, the reference's 0.8); "
        "1 of 44 vertices differs by more than 0.01. 1 vertex with a weight outside [0, 1] (the reference's: 0); "
        "1 vertex whose weights do not sum to 1 (the reference's: 0)."
    )
    assert [f["label"] for f in view["fields"]] == [
        "difference from the reference's weights (largest over the handles)",
        "weight of handle 1 (darker outside [0, 1])", "weight of handle 2 (darker outside [0, 1])",
    ]
    levels = view["data"]["c"]
    assert len(levels) == 3 and levels[0][0][k] == LEVELS and max(levels[0][0][:k] + levels[0][0][k + 1:]) == 0
    lo, hi = -0.2, 1.2
    assert levels[2][0][k] == round((1.11 - lo) / (hi - lo) * LEVELS) and levels[2][1][k] == round((0.8 - lo) / (hi - lo) * LEVELS)


def _planted_output(function: str, case, ref):
    """The reference's output with one vertex moved by 0.31: what a nearly right student returns."""
    if function == "arap_solve":
        U = np.array(ref[0], float)
        U[3] += 0.31
        return (U, np.asarray(ref[1], float))
    W = np.array(ref, float)
    W[3] += 0.31
    return W


@pytest.mark.parametrize("function", PICTURED)
def test_the_data_of_every_hidden_case_is_numbers_only_and_matches_the_case(function):
    cases, expected = hidden_cases(function, SEED)
    for case, ref in zip(cases, expected):
        view = view_for(function, case, _planted_output(function, case, ref), ref)
        data = view["data"]
        assert numbers_only(data) == [], case.label
        # the mesh is the first step's (V, F), or kept in the case's context where the kernel gets a matrix
        V, F = (np.asarray(x) for x in case.context.get("mesh", case.steps[0].args[:2]))
        n, d = V.shape
        assert data["d"] == d and data["q"] == QUANT and data["f"] == F.ravel().tolist()
        assert all(len(p) == n * d and max(map(abs, p)) <= FAR * QUANT for p in data["p"])
        assert all(len(c) == n and 0 <= min(c) and max(c) <= LEVELS for pair in data["c"] for c in pair)
        assert all(0 <= v < n for group in data["h"] for v in group) and data["w"] == 3
        assert "vertex 3" in view["description"]
        # the reference's positions come back from the quantization to within half a step
        reference = np.asarray({"arap_solve": ref[0], "laplacian_editing": ref}.get(function, V), float)
        if function == "k_harmonic_solve":  # displacements: the view draws V + D
            reference = V + np.asarray(ref, float)
        lo, hi = reference.min(axis=0), reference.max(axis=0)
        half = (hi - lo).max() / 2
        back = np.asarray(data["p"][1]).reshape(n, d) / QUANT * half + (lo + hi) / 2
        assert np.abs(back - reference).max() <= 0.5001 * half / QUANT


HOSTILE = {
    "strings": lambda n, d: np.array([["<script>alert(1)</script>"] * d] * n),
    "a list of strings": lambda n, d: [["</script><img src=x onerror=alert(1)>"] * d] * n,
    "objects": lambda n, d: np.array([[object()] * d] * n, dtype=object),
    "NaN": lambda n, d: np.full((n, d), np.nan),
    "one inf": lambda n, d: np.where(np.arange(n * d).reshape(n, d) == 5, np.inf, 0.0),
    "a complex array": lambda n, d: np.ones((n, d)) * 1j,
    "the wrong shape": lambda n, d: np.zeros((n + 1, d)),
    "a transposed array": lambda n, d: np.zeros((d, n)),
    "a sparse matrix with NaN": lambda n, d: sp.csr_matrix(np.full((n, d), np.nan)),
    "None": lambda n, d: None,
    "a dict": lambda n, d: {"x": 1},
    "overflowing numbers": lambda n, d: [[10 ** 400] * d] * n,
}


@pytest.mark.parametrize("kind", HOSTILE)
@pytest.mark.parametrize("function", ["laplacian_editing", "bbw", "k_harmonic_solve"])
def test_a_student_output_holding_strings_or_nan_gets_no_view(function, kind):
    cases, expected = hidden_cases(function, SEED)
    case, ref = cases[0], expected[0]
    n, d = np.shape(ref)
    view = view_for(function, case, HOSTILE[kind](n, d), ref)
    assert view == {"skipped": f"No interactive view: your output is not a finite numeric array of shape ({n}, {d})."}


def test_an_arap_solve_output_that_is_not_a_pair_gets_no_view():
    cases, expected = hidden_cases("arap_solve", SEED)
    n, d = np.shape(expected[0][0])
    for value in (np.asarray(expected[0][0]), (np.asarray(expected[0][0]),), "(U, energies)"):
        assert "skipped" in view_for("arap_solve", cases[0], value, expected[0])


def test_a_mesh_above_the_vertex_budget_is_not_shown_and_the_page_says_so():
    V, F = shapes.grid_2d(80, 80)
    assert len(V) > VERTEX_BUDGET
    view = deformation_view(V, F, np.array([0]), V, V)
    assert view == {"skipped": f"This mesh has {len(V):,} vertices and {len(F):,} triangles, more than the interactive view "
                               f"shows ({VERTEX_BUDGET:,} vertices, 10,000 triangles); the picture above shows it whole."}


def test_a_student_vertex_far_away_is_drawn_at_the_edge_and_noted():
    V, F, handles, _ = folded_strip()
    U = V.copy()
    U[5] = [1e12, -1e12]
    view = deformation_view(V, F, handles, U, V)
    assert max(map(abs, view["data"]["p"][0])) == FAR * QUANT
    assert view["notes"] == ["1 of your vertices lie more than 8 half-widths of the reference's result from its centre; "
                             "they are drawn at that distance."]
    assert "1e+12" in view["description"]


def page(outputs: dict) -> str:
    """The feedback page of functions whose hidden cases returned ``outputs[function](case, reference output)``."""
    results = []
    for function, output in outputs.items():
        cases, expected = hidden_cases(function, SEED)
        collected = Collected(function, [CaseOutput(output(c, r), None, 0.1) for c, r in zip(cases, expected)], None)
        results.append((GradedCell(f"test_{function}", function, 4.0), verify(function, SEED, collected, None), collected))
    spec = UnitSpec(student_id="ada", notebook="03_arap", submission=b"{}", source=nbformat.writes(nbformat.v4.new_notebook()), seed=SEED)
    return feedback_html(spec, results, [])


def planted(function):
    return lambda case, ref: _planted_output(function, case, ref)


def scripts(text: str) -> list[tuple[str, str]]:
    return re.findall(r"<script([^>]*)>(.*?)</script>", text, re.S)


def test_the_page_runs_only_the_viewer_once_under_a_policy_that_forbids_connections():
    text = page({"laplacian_editing": planted("laplacian_editing"), "bbw": planted("bbw")})
    executable = [body for attrs, body in scripts(text) if "application/json" not in attrs]
    assert executable == [feedback_view.VIEWER_JS]
    digest = base64.b64encode(hashlib.sha256(executable[0].encode()).digest()).decode()
    policy = html.unescape(re.search(r'<meta http-equiv="Content-Security-Policy" content="([^"]+)">', text).group(1))
    directives = dict(part.strip().split(" ", 1) for part in policy.split(";"))
    assert directives["default-src"] == "'none'" and directives["connect-src"] == "'none'"
    assert directives["script-src"] == f"'sha256-{digest}'"
    assert directives["img-src"] == "data:"
    blocks = [body for attrs, body in scripts(text) if "application/json" in attrs]
    assert len(blocks) == 2 and re.findall(r'id="dl-view-(\d+)-title"', text) == ["0", "1"]
    for body in blocks:
        assert numbers_only(json.loads(body)) == []
    assert not re.search(r"(src|href)\s*=\s*\"(?!data:)", text), "nothing is loaded from outside the page"


def test_a_page_without_a_view_keeps_the_policy_and_runs_no_script():
    spec = UnitSpec(student_id="<script>x</script>", notebook="03_arap", submission=None,
                    source=nbformat.writes(nbformat.v4.new_notebook()), seed=SEED)
    text = feedback_html(spec, [], ["<script>alert(1)</script>"])
    assert "<script" not in text and "connect-src &#39;none&#39;" in text


@pytest.mark.parametrize("kind", ["NaN", "strings"])
def test_a_nan_or_string_output_reaches_no_view_on_the_page(kind):
    text = page({"laplacian_editing": lambda case, ref: HOSTILE[kind](*np.shape(ref))})
    assert scripts(text) == [] and "<script>alert" not in text and 'class="dl-interactive"' not in text
    if kind == "NaN":  # matplotlib still draws the picture; the view beside it says why it is missing
        assert '<p class="dl-note">No interactive view: your output is not a finite numeric array of shape (44, 2).</p>' in text


def test_the_picture_and_the_view_show_a_failed_case_rather_than_the_first():
    cases, expected = hidden_cases("laplacian_editing", SEED)
    wrong = cases[2]
    text = page({"laplacian_editing": lambda case, ref: _planted_output("laplacian_editing", case, ref) if case is wrong
                 else np.asarray(ref, float)})
    captions = re.findall(r"<figcaption>([^<]*)</figcaption>", text)
    assert captions and captions[0].startswith(f"laplacian_editing, {html.escape(wrong.label)}:")
    description = html.unescape(re.search(r'class="dl-description"[^>]*>([^<]*)', text).group(1))
    assert description.startswith(f"Largest difference from the reference's position: {0.31 * np.sqrt(2):.3g} at vertex 3")
