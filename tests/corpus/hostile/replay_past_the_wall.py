import nbformat

NOTEBOOK = "01_shape_matching"
STATUS = "graded-with-incidents"
EVENT = "wall-clock limit"
DESCRIPTION = (
    "five added cells sleep 7 s each (under the 10 s cell timeout), then centroid() kills the kernel, so every "
    "restart would replay 35 s of cells: replays must count against the notebook's wall limit"
)


def EDIT(nb):
    for _ in range(5):
        nb.cells.append(nbformat.v4.new_code_cell("import time\ntime.sleep(7)"))
    return nb


def CHECK(result, autograded, params):
    limit = float(params["WALL"]) + 20  # start-up and shutdown of the last kernel
    return [] if result["duration_s"] <= limit else [f"the notebook ran {result['duration_s']:.0f} s, past its wall limit"]


SOLUTIONS = {
    "centroid": '''import os


def centroid(P, w=None):
    os._exit(1)
''',
}
LOSES = {"centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align"}
