import json

import nbformat

NOTEBOOK = "00_meshes"
STATUS = "invalid"
DESCRIPTION = "a cell's metadata is nested 100,000 deep"


def EDIT(nb):
    text = nbformat.writes(nb)
    raw = json.loads(text)
    raw["cells"][0]["metadata"]["deep"] = "@@NEST@@"
    return json.dumps(raw).replace('"@@NEST@@"', "[" * 100_000 + "]" * 100_000).encode()


SOLUTIONS = {}
LOSES = {"edges", "euler_characteristic", "boundary_loop_count", "genus"}
