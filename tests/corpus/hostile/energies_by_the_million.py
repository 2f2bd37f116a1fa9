import nbformat

NOTEBOOK = "03b_arap_global"
DESCRIPTION = (
    "an added cell makes arap_solve return 3e7 energies for the first case the grader collects (240 MB, which the "
    "grader must neither load nor plot; every case would fill the student's own 512 MiB workdir)"
)
_WRAPPER = '''import sys

import numpy as np

_honest_arap_solve = globals()["arap_solve"]
_flooded = []


def _flooding_arap_solve(data, handle_positions, U0=None, iterations=10):
    U, energies = _honest_arap_solve(data, handle_positions, U0, iterations)
    caller = sys._getframe(1)
    # the grader collecting arap_solve itself (other collections call it as an intermediate step)
    if caller.f_code.co_name == "__deformlab_collect__" and caller.f_locals.get("function") == "arap_solve" and not _flooded:
        _flooded.append(True)
        return U, np.linspace(1.0, 0.0, 30_000_000)
    return U, energies


globals()["arap_solve"] = _flooding_arap_solve
'''


def EDIT(nb):
    nb.cells.append(nbformat.v4.new_code_cell(_WRAPPER))
    return nb


SOLUTIONS = {}
LOSES = {"arap_solve"}
