"""Cell metadata that formgrader's template prints unescaped: a grade id that closes its attribute, 1000 points."""

import runpy
from pathlib import Path

import nbformat

attack = runpy.run_path(str(Path(__file__).with_name("_formgrader_attack.py")))["attack"]

NOTEBOOK = "00_meshes"
DESCRIPTION = "an added graded markdown cell whose grade_id is markup, tags with markup, the short answer made worth 1000 points"
SOLUTIONS = {}
LOSES = set()


def EDIT(nb):
    index, answer = next((i, c) for i, c in enumerate(nb.cells) if (c.metadata.get("nbgrader") or {}).get("grade_id") == "answer_nut")
    answer.metadata["nbgrader"]["points"] = 1000
    answer.metadata["tags"] = ['"><script>alert(1)</script>']
    forged = nbformat.v4.new_markdown_cell("An extra answer.")
    forged.metadata["nbgrader"] = {
        "grade": True, "solution": True, "locked": False, "points": 1, "schema_version": 3,
        "grade_id": f'x"><img src=x onerror="{attack("grade-id")}"><b x="',
    }
    nb.cells.insert(index + 1, forged)
    return nb
