"""A notebook saved under a name of markup and a terminal escape, without the metadata that names its notebook."""

NOTEBOOK = "00_meshes"
FILENAME = "<img src=x onerror=alert(1)>\x1b[2J.ipynb"
DESCRIPTION = "00_meshes handed in as '<img src=x onerror=alert(1)>ESC[2J.ipynb' with its metadata stripped"
STATUS = "missing"
SOLUTIONS = {}
LOSES = {"edges", "euler_characteristic", "boundary_loop_count", "genus"}


def EDIT(nb):
    nb.metadata.pop("deformlab", None)
    return nb


def CHECK(result, autograded, params):
    problems = []
    shown = "'<img src=x onerror=alert(1)>?[2J.ipynb'"
    if not any(shown in note and "no notebook of this assignment claims" in note for note in result["notes"]):
        problems.append(f"no note names the unclaimed file as {shown}: {result['notes']}")
    page = result.get("feedback_html") or ""
    if "&lt;img src=x" not in page:
        problems.append("the feedback page does not show the file's name, escaped")
    if "<img src=x" in page or "\x1b" in page:
        problems.append("the feedback page shows the file's name as markup or with its terminal escape")
    return problems
