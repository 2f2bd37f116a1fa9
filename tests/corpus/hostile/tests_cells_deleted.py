NOTEBOOK = "02_sign_correction"
DESCRIPTION = "every tests cell deleted (correct solutions): the grader restores them"


def EDIT(nb):
    nb.cells = [c for c in nb.cells if not (c.metadata.get("nbgrader") or {}).get("grade_id", "").startswith("test_")]
    return nb


SOLUTIONS = {}
LOSES = set()
