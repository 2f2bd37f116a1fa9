"""A definition cell displays scripts that would rewrite the gradebook in a TA's formgrader page."""

import runpy
from pathlib import Path

attack = runpy.run_path(str(Path(__file__).with_name("_formgrader_attack.py")))["attack"]

NOTEBOOK = "00_meshes"
DESCRIPTION = "the edges solution cell displays <script> (HTML, Javascript, Markdown, a _repr_html_ result) aimed at formgrader"
SOLUTIONS = {}
LOSES = set()

# After the solution, so that _Shown() is the cell's result (an execute_result output).
ATTACK = f'''
from IPython.display import HTML, Javascript, Markdown, display

display(HTML("""<script>{attack("html-script")}</script>"""))
display(Javascript("""{attack("javascript")}"""))
display(Markdown("""<img src=x onerror="{attack("markdown-output")}">"""))
display({{"text/html": """<img src=x onerror="{attack("html-bundle")}">""", "text/plain": "nothing to see"}}, raw=True)
display(HTML("""<details open ontoggle="{attack("html-details")}">"""), metadata={{"isolated": False}})


class _Shown:
    def _repr_html_(self):
        return """<script>{attack("repr-html")}</script>"""


_Shown()
'''


def EDIT(nb):
    cell = next(c for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("grade_id") == "solution_edges")
    cell.source = cell.source + "\n" + ATTACK
    return nb
