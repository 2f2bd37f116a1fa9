NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_mass_matrix() is igl.massmatrix from the extension module imported again after del sys.modules"
SOLUTIONS = {
    "tet_mass_matrix": '''import importlib
import sys

import numpy as np


def tet_mass_matrix(V, T):
    # a fresh copy of the extension module: CPython hands back its original functions
    del sys.modules["igl.pyigl_core"]
    core = importlib.import_module("igl.pyigl_core")
    return core.massmatrix(np.asarray(V, dtype=float), np.asarray(T, dtype=np.int64))
''',
}
LOSES = {"tet_mass_matrix"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "tet_mass_matrix")
    problems = [] if "igl.massmatrix" in test["summary"] and test["score"] == 0 else [f"tet_mass_matrix: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.massmatrix"] else [f"policy_violations {test.get('policy_violations')!r}"])
