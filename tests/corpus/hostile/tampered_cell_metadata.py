import json

import nbformat

NOTEBOOK = "01_shape_matching"
DESCRIPTION = (
    "every graded cell's metadata claims 1000 points, the tests cells are unlocked and renamed, and an added cell "
    "poses as a graded tests cell worth 1000 points"
)


def EDIT(nb):
    for cell in nb.cells:
        meta = cell.metadata.get("nbgrader")
        if meta:
            meta["points"] = 1000
            meta["locked"] = False
    nb.cells.append(
        nbformat.v4.new_code_cell(
            "assert True",
            metadata={"nbgrader": {"grade": True, "solution": False, "locked": True, "points": 1000, "grade_id": "test_bonus_points", "schema_version": 3}},
        )
    )
    return nb


def CHECK(result, autograded, params):
    """The executed notebook's graded cells are the source's, with the source's points."""
    cells = json.loads(autograded)["cells"] if autograded else []
    claimed = {(c["metadata"].get("nbgrader") or {}).get("grade_id"): (c["metadata"].get("nbgrader") or {}).get("points") for c in cells}
    problems = [f"{gid} keeps {points} points" for gid, points in claimed.items() if points == 1000]
    if "test_bonus_points" in claimed:
        problems.append("the forged graded cell test_bonus_points kept its grade metadata")
    return problems


SOLUTIONS = {}
LOSES = set()
