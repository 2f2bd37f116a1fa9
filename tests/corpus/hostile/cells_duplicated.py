import copy

NOTEBOOK = "00_meshes"
DESCRIPTION = "every tests and solution cell duplicated at the end (the copy of test_edges reduced to `assert True`), all cell ids the same"


def EDIT(nb):
    copies = [copy.deepcopy(c) for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("grade_id")]
    for c in copies:
        if (c.metadata.get("nbgrader") or {}).get("grade_id") == "test_edges":
            c.source = "assert True"
    nb.cells += copies
    for c in nb.cells:
        c["id"] = "same"
    return nb


SOLUTIONS = {}
# the copied solution cells run after the originals: a copy of a right solution is still right
LOSES = set()
