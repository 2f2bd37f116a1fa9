"""What reaches a TA's browser: executed notebooks keep no active content (grader/pipeline/neutralize.py).

The pages are rendered exactly as formgrader renders a submission and ``nbgrader generate_feedback``
a feedback page (nbconvert's HTMLExporter with nbgrader's ``formgrade`` or ``feedback`` template) and parsed: a neutralized attacker's page may hold no script,
event handler, frame or script link that the honest student's page does not.
"""

from __future__ import annotations

import base64
import copy
import io
import json
import re
import runpy
from html.parser import HTMLParser
from pathlib import Path

import nbformat
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from nbconvert.exporters import HTMLExporter
from nbgrader.server_extensions.formgrader import handlers
from PIL import Image
from traitlets.config import Config

from tests.corpus import load_entry, student_notebook
from grader.pipeline.neutralize import (
    MAX_CELL_OUTPUT_BYTES,
    MAX_NOTEBOOK_OUTPUT_BYTES,
    MAX_OUTPUTS_PER_CELL,
    MAX_OUTPUTS_PER_NOTEBOOK,
    neutralize,
)

ROOT = Path(__file__).resolve().parents[2]
HOSTILE = ROOT / "tests" / "corpus" / "hostile"
attack = runpy.run_path(str(HOSTILE / "_formgrader_attack.py"))["attack"]
SCRIPT_SCHEMES = ("javascript:", "vbscript:", "livescript:")


def png_base64(size=(4, 3)) -> str:
    buf = io.BytesIO()
    Image.new("RGB", size, (200, 30, 30)).save(buf, format="PNG")
    return base64.b64encode(buf.getvalue()).decode()


class Active(HTMLParser):
    """The active parts of an HTML page: scripts, event handlers, frames, embedded SVG, script links."""

    def __init__(self, html: str):
        super().__init__(convert_charrefs=True)
        self.found: set[str] = set()
        self._script: list[str] | None = None
        self.feed(html)

    def handle_starttag(self, tag, attrs):
        if tag == "script":
            self._script = [dict(attrs).get("src") or ""]
        if tag in ("iframe", "frame", "object", "embed", "svg", "math", "base", "form", "meta", "link"):
            self.found.add(f"<{tag} {sorted(attrs)}>" if tag in ("meta", "link") else f"<{tag}>")
        for name, value in attrs:
            if name.startswith("on"):
                self.found.add(f"{tag} {name}={value}")
            if value and name in ("href", "src", "action", "formaction", "xlink:href", "data", "srcdoc"):
                squeezed = re.sub(r"[\x00-\x20]", "", value).lower()
                if squeezed.startswith(SCRIPT_SCHEMES) or name == "srcdoc" or squeezed.startswith("data:text/html"):
                    self.found.add(f"{tag} {name}={value}")

    def handle_data(self, data):
        if self._script is not None:
            self._script.append(data)

    def handle_endtag(self, tag):
        if tag == "script" and self._script is not None:
            # The template's own scripts differ per page only in generated ids.
            self.found.add("<script>" + re.sub(r"[0-9a-f]{8}-[0-9a-f-]{27}", "ID", "".join(self._script)))
            self._script = None


def nbgrader_page(nb, template: str = "formgrade") -> str:
    """The page nbgrader makes of ``nb``: formgrader's submission page, or ``generate_feedback``'s ``feedback``."""
    config = Config()
    config.HTMLExporter.template_name = template
    config.HTMLExporter.extra_template_basedirs = [handlers.template_path]
    # generate_feedback inlines bootstrap's CSS from formgrader's static files
    config.HTMLExporter.extra_template_paths = [str(Path(handlers.static_path) / "node_modules" / "bootstrap" / "dist" / "css")]
    resources = {"assignment_id": "deformation", "notebook_id": "00_meshes", "submission_id": "s1", "index": 0,
                 "total": 1, "base_url": "", "student": "x", "last_name": None, "first_name": None, "notebook_path": "x",
                 "nbgrader": {"notebook": "00_meshes", "score": 0, "max_score": 11, "late_penalty": 0}}
    if template == "feedback":  # nbgrader's GetGrades puts each graded cell's score in its metadata
        nb = copy.deepcopy(nb)
        for cell in nb.cells:
            if (cell.metadata.get("nbgrader") or {}).get("grade"):
                cell.metadata.nbgrader["score"] = 0
    return HTMLExporter(config=config).from_notebook_node(nb, resources=resources)[0]


def rendered_markdown(cell) -> str:
    """A markdown cell as nbconvert's HTML exporter renders it (with the cell's attachments)."""
    return HTMLExporter().markdown2html({"cell": cell}, cell.source)


@pytest.fixture(scope="module")
def source(source_notebooks):
    return nbformat.read(source_notebooks["00_meshes"], as_version=4)


def gid(cell):
    return (cell.metadata.get("nbgrader") or {}).get("grade_id")


def cell_of(nb, grade_id):
    return next(c for c in nb.cells if gid(c) == grade_id)


def hostile_outputs() -> list:
    """What a definition cell's display calls produce in the kernel, one vector per output."""
    new = nbformat.v4.new_output
    fake_png = base64.b64encode(f'\x89PNG"><img src=x onerror="{attack("fake-png")}">'.encode()).decode()
    return [
        new("display_data", data={"text/html": f"<script>{attack('html-script')}</script>", "text/plain": "<HTML>"}),
        new("display_data", data={"application/javascript": attack("javascript"), "text/plain": "<JS>"}),
        new("display_data", data={"text/markdown": f'<img src=x onerror="{attack("markdown-output")}">'}),
        new("display_data", data={"image/svg+xml": f'<svg onload="{attack("svg-onload")}"/>'}),
        new("display_data", data={"application/vnd.jupyter.widget-view+json": {"model_id": "m1", "version_major": 2}}),
        new("display_data", data={"image/png": fake_png, "text/plain": "a picture"}),
        new("display_data", data={"image/png": png_base64()},
            metadata={"image/png": {"alt": f'x" onerror="{attack("png-alt")}', "width": f"1 onerror={attack('png-width')}"},
                      "filenames": {"image/png": f'x" onerror="{attack("png-file")}'}}),
        new("display_data", data={"text/latex": rf"$\href{{javascript:{attack('latex')}}}{{x}}$", "application/pdf": "JVBERi0="}),
        new("execute_result", data={"text/html": f"<script>{attack('repr-html')}</script>", "text/plain": "<obj>"},
            execution_count=3, metadata={"text/html": {"isolated": False}}),
    ]


# The vectors of attacked_notebook that nbgrader's pages make live (the others it escapes).
LIVE_VECTORS = {"html-script", "javascript", "markdown-output", "repr-html", "answer-img", "answer-script",
                "answer-iframe", "click-answer-link", "click-answer-entity", "markdown-svg", "grade-id"}


def vectors(found: set[str]) -> set[str]:
    """The attack vectors named in the active parts ``found``."""
    scripts = [*found, *(base64.b64decode(b).decode() for item in found for b in re.findall(r"atob\((?:'|%27)([A-Za-z0-9+/=]+)", item))]
    return {name for item in scripts for name in re.findall(r"\}\)\('([a-z0-9-]+)'\)", item)}


def attacked_notebook(source) -> nbformat.NotebookNode:
    """Every vector at once: hostile outputs, widget state, and the markdown, raw and metadata corpus entries' edits."""
    nb = student_notebook(source, {})
    for name in ("markdown_answer_with_html", "cell_metadata_injects_html"):
        nb = load_entry(HOSTILE / f"{name}.py").edit(nb)
    cell_of(nb, "solution_edges").outputs = hostile_outputs()
    nb.metadata["widgets"] = {"application/vnd.jupyter.widget-state+json": {"state": {"m1": {
        "model_name": "HTMLModel", "model_module": "@jupyter-widgets/controls", "model_module_version": "2.0.0",
        "state": {"value": f'<img src=x onerror="{attack("widget-state")}">'}}}, "version_major": 2, "version_minor": 0}}
    return nb


@pytest.mark.parametrize("template", ["formgrade", "feedback"])
def test_an_attackers_nbgrader_page_has_no_active_content_beyond_an_honest_students(source, template):
    honest = student_notebook(source, {})
    neutralize(honest, source)
    baseline = Active(nbgrader_page(honest, template)).found
    raw = attacked_notebook(source)
    # The test can fail: unneutralized, the page is full of the student's scripts.
    unsafe = Active(nbgrader_page(raw, template)).found - baseline
    assert vectors(unsafe) == LIVE_VECTORS, sorted(unsafe)
    notes = neutralize(raw, source)
    extra = Active(nbgrader_page(raw, template)).found - baseline
    assert not extra, "\n".join(sorted(extra))
    assert notes, "what was removed is reported"


def test_display_outputs_keep_only_plain_text_and_pngs_that_are_png_files(source):
    nb = student_notebook(source, {})
    cell = cell_of(nb, "solution_edges")
    cell.outputs = hostile_outputs()
    notes = neutralize(nb, source)
    kept = [(o.output_type, sorted(o.get("data", {}))) for o in cell.outputs]
    assert kept == [("display_data", ["text/plain"])] * 6 + [("display_data", ["image/png"])] + [
        ("display_data", ["text/plain"]), ("execute_result", ["text/plain"])]
    assert cell.outputs[6].data["image/png"] == png_base64()
    assert all(o.metadata == {} for o in cell.outputs) and cell.outputs[-1].execution_count == 3
    assert "the grader removed this output's text/html" in cell.outputs[0].data["text/plain"]
    assert cell.outputs[0].data["text/plain"].startswith("<HTML>"), "the plain text shown beside the HTML is kept"
    assert "image/png that is not a PNG file" in cell.outputs[5].data["text/plain"]
    assert any("application/javascript" in n and "image/svg+xml" in n for n in notes)


def test_stream_text_and_error_tracebacks_are_kept_as_they_were(source):
    nb = student_notebook(source, {})
    cell = cell_of(nb, "solution_edges")
    cell.outputs = [
        nbformat.v4.new_output("stream", name="stdout", text="edges: <b>12</b>\n"),
        nbformat.v4.new_output("stream", name="stderr", text="warning\n"),
        nbformat.v4.new_output("error", ename="ValueError", evalue="bad <F>", traceback=["\x1b[31mValueError\x1b[0m: bad <F>"]),
    ]
    expected = copy.deepcopy(cell.outputs)
    assert neutralize(nb, source) == []
    assert cell.outputs == expected


def test_notebook_metadata_is_the_sources_without_widget_state(source):
    nb = attacked_notebook(source)
    nb.metadata["language_info"] = {"name": "python", "pygments_lexer": "html"}
    neutralize(nb, source)
    assert nb.metadata == {k: v for k, v in source.metadata.items() if k != "widgets"}


def test_cell_metadata_is_restored_from_the_source_and_forged_grade_cells_lose_theirs(source):
    nb = load_entry(HOSTILE / "cell_metadata_injects_html.py").edit(student_notebook(source, {}))
    neutralize(nb, source)
    assert cell_of(nb, "answer_nut").metadata == cell_of(source, "answer_nut").metadata, "points 1000 and tags are gone"
    ids = [gid(c) for c in nb.cells if gid(c)]
    assert ids == [gid(c) for c in source.cells if gid(c)], "the forged grade cell is an ordinary cell again"
    assert all(c.metadata == {} for c in nb.cells if not gid(c))


def test_outputs_are_capped_per_cell_and_per_notebook_in_count_and_bytes(source):
    nb = student_notebook(source, {})
    code = [c for c in nb.cells if c.cell_type == "code"]
    many = [nbformat.v4.new_output("stream", name="stdout", text=f"{k}\n") for k in range(3 * MAX_OUTPUTS_PER_CELL)]
    big = [nbformat.v4.new_output("display_data", data={"text/plain": "x" * 2**19}) for _ in range(8)]
    code[0].outputs, code[1].outputs = many, big
    for cell in code[2:]:  # the rest fill the notebook's budgets
        cell.outputs = [nbformat.v4.new_output("display_data", data={"image/png": png_base64((600, 600))})] * 30
    neutralize(nb, source)
    assert len(code[0].outputs) == MAX_OUTPUTS_PER_CELL + 1 and "dropped 200 more" in code[0].outputs[-1].text
    assert [o.text for o in code[0].outputs[:3]] == ["0\n", "1\n", "2\n"], "the first outputs are the ones kept"
    assert len(json.dumps(code[1].outputs)) < MAX_CELL_OUTPUT_BYTES + 1000 and "dropped" in code[1].outputs[-1].text
    kept = [o for c in code for o in c.outputs if "dropped" not in o.get("text", "")]
    assert len(kept) <= MAX_OUTPUTS_PER_NOTEBOOK
    assert sum(len(json.dumps(o)) for o in kept) <= MAX_NOTEBOOK_OUTPUT_BYTES


def test_instructor_markdown_and_raw_cells_are_kept_exactly(source):
    nb = student_notebook(source, {})
    nb.cells.append(nbformat.v4.new_raw_cell("<b>note</b>"))
    src = copy.deepcopy(source)
    src.cells.append(nbformat.v4.new_raw_cell("<b>note</b>"))
    before = [c.source for c in nb.cells if c.cell_type != "code"]
    assert any("<" in text for text in before), "the instructor's own text has markup worth keeping"
    neutralize(nb, src)
    assert [c.source for c in nb.cells if c.cell_type != "code"] == before


# Pieces of markup and of markdown syntax an answer could combine to smuggle in a script.
FRAGMENTS = [
    "<script>alert(1)</script>", "<img src=x onerror=alert(1)>", "<iframe src='javascript:alert(1)'>", "<svg onload=alert(1)>",
    "<!--", "-->", "<", ">", "&", "&#60;", "&lt;", "&#x3c;", "&#58;", "&#9;", "\\", "\\<", "\\:", "javascript", "JavaScript",
    "vbscript", ":", "alert(1)", "[x](", "](", ")", "![x](", "[r]: ", "[r]", "<http://a>", "<javascript:alert(1)>", "`", "```\n",
    "$", "$$", "\\href{", "}", "{", " ", "\n", "\n\n", "\t", "#", "*", "_", "'", '"', "=", "onerror=", "<a href=", "x",
    "![a](attachment:", "attachment:", "a.png", "b.svg", "%20", "&amp;", "&amp;#58;", "&#115;", "&colon;", "%3A",
    "[x](javascript&#58;alert(1))", "[x](java&#115;cript:alert(1))", "[x](javascript\\:alert(1))",
    "[x](javascript&amp;#58;alert(1))", "[r]: javascript&colon;alert(1)\n\n[r]", "![a](attachment:b.svg)",
    "![a](attachment:a.png'x)", "(1)", "![a](attachment:a.png)", "(", "![a](attachment:a.png",
]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.sampled_from(FRAGMENTS), max_size=14))
def test_a_students_markdown_renders_as_inert_text_with_nbconvert(source, parts):
    nb = student_notebook(source, {})
    answer = cell_of(nb, "answer_nut")
    answer.source = "".join(parts)
    answer["attachments"] = {"a.png": {"image/png": png_base64()}, "b.svg": {"image/svg+xml": "<svg onload=alert(1)/>"}}
    neutralize(nb, source)
    page = rendered_markdown(answer)  # raises if a reference to a missing attachment is left
    assert not Active(page).found, f"{answer.source!r} renders as {page!r}"


def test_a_students_markdown_shows_its_markup_as_text(source):
    nb = load_entry(HOSTILE / "markdown_answer_with_html.py").edit(student_notebook(source, {}))
    neutralize(nb, source)
    answer = cell_of(nb, "answer_nut")
    shown = re.sub(r"<[^>]+>", "", rendered_markdown(answer))
    assert "&lt;script&gt;" in shown and "&lt;img src=x onerror=" in shown, "the TA sees what the student wrote"
    assert "attachments" not in answer
    raw = next(c for c in nb.cells if c.cell_type == "raw")
    assert raw.source.startswith("&lt;script&gt;")
