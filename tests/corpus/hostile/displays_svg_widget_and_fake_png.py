"""A definition cell shows active content through other output types: SVG, widgets, a fake PNG, LaTeX."""

import runpy
from pathlib import Path

attack = runpy.run_path(str(Path(__file__).with_name("_formgrader_attack.py")))["attack"]

NOTEBOOK = "00_meshes"
DESCRIPTION = "the genus solution cell displays an SVG with onload, an HTML widget, a PNG that is HTML, output metadata with markup"
SOLUTIONS = {}
LOSES = set()

ATTACK = f'''
import base64

import ipywidgets
from IPython.display import display

display({{"image/svg+xml": """<svg xmlns="http://www.w3.org/2000/svg" onload="{attack("svg-onload")}"><circle r="5"/></svg>"""}}, raw=True)
display(ipywidgets.HTML("""<img src=x onerror="{attack("widget-html")}">"""))
_fake = base64.b64encode(b"""\\x89PNG"><img src=x onerror="{attack("fake-png")}">""").decode()
display({{"image/png": _fake, "text/plain": "a picture"}}, raw=True)
display(
    {{"image/png": "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="}},
    metadata={{"image/png": {{"alt": """x" onerror="{attack("png-alt")}""", "width": """1 onerror={attack("png-width")}"""}}}},
    raw=True,
)
display({{"text/latex": r"""$\\href{{javascript:{attack("click-latex-href")}}}{{\\text{{click}}}}$""", "text/markdown": """<img src=x onerror="{attack("markdown-bundle")}">"""}}, raw=True)
'''


def EDIT(nb):
    cell = next(c for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("grade_id") == "solution_genus")
    cell.source = cell.source + "\n" + ATTACK
    return nb
