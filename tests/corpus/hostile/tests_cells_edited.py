NOTEBOOK = "05_lbs"
DESCRIPTION = "tests cells replaced by `assert True` or by a wrong redefinition, unlocked, worth 100 points, kernelspec changed"


def EDIT(nb):
    for cell in nb.cells:
        meta = cell.metadata.get("nbgrader") or {}
        if meta.get("grade_id") == "test_lbs_matrix":
            cell.source = "assert True"
            meta["points"] = 100
        elif meta.get("grade_id") == "test_lbs":
            # turned into an unlocked solution cell that overrides lbs with a wrong one
            cell.source = "def lbs(V, W, T):\n    return V\n"
            meta.update(locked=False, solution=True, grade=False)
    nb.metadata["kernelspec"] = {"name": "evil", "display_name": "evil", "language": "python"}
    return nb


SOLUTIONS = {}
LOSES = set()
