import json

import nbformat

NOTEBOOK = "02_sign_correction"
DESCRIPTION = "a markdown cell holds a lone surrogate (\\ud800), which JSON allows and UTF-8 cannot encode"


def EDIT(nb):
    nb.cells.append(nbformat.v4.new_markdown_cell("placeholder"))
    raw = json.loads(nbformat.writes(nb))
    raw["cells"][-1]["source"] = "caf\ud800 au lait"
    return json.dumps(raw).encode()  # ensure_ascii keeps the surrogate as the escape \\ud800


SOLUTIONS = {}
LOSES = set()
