NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs_matrix() is igl.lbs_matrix, reached through importlib.import_module"
SOLUTIONS = {
    "lbs_matrix": '''import importlib

import numpy as np


def lbs_matrix(V, W):
    library = importlib.import_module("i" + "gl")
    return library.lbs_matrix(np.asarray(V, dtype=float), np.asarray(W, dtype=float))
''',
}
LOSES = {"lbs_matrix"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "lbs_matrix")
    problems = [] if "igl.lbs_matrix" in test["summary"] and test["score"] == 0 else [f"lbs_matrix: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.lbs_matrix"] else [f"policy_violations {test.get('policy_violations')!r}"])
