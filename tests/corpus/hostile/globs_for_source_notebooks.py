NOTEBOOK = "02_sign_correction"
DESCRIPTION = "rigid_align() globs the filesystem for assignments/source notebooks and runs the instructor's solution cell"
SOLUTIONS = {
    "rigid_align": '''import glob
import json


def rigid_align(P, Q, w=None):
    found = sorted(glob.glob("@@REPO@@/assignments/source/*/02_sign_correction.ipynb"))
    found += sorted(glob.glob("/*/*/assignments/source/*/02_sign_correction.ipynb"))
    found += sorted(glob.glob("/tmp/**/source/*/02_sign_correction.ipynb", recursive=True))
    if not found:
        raise FileNotFoundError("no instructor notebook in sight")
    with open(found[0]) as fh:
        cells = json.load(fh)["cells"]
    namespace = dict(globals())
    for cell in cells:
        if cell["metadata"].get("nbgrader", {}).get("grade_id") == "solution_rigid_align":
            exec("".join(cell["source"]), namespace)
    return namespace["rigid_align"](P, Q, w)
''',
}
LOSES = {"rigid_align"}
