NOTEBOOK = "00_meshes"
DESCRIPTION = "euler_characteristic() is igl.euler_characteristic (genus calls it: only euler_characteristic loses)"
SOLUTIONS = {
    "euler_characteristic": '''import igl
import numpy as np


def euler_characteristic(V, F):
    return int(igl.euler_characteristic(np.asarray(F, dtype=np.int64)))
''',
}
LOSES = {"euler_characteristic"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "euler_characteristic")
    problems = [] if "igl.euler_characteristic" in test["summary"] and test["score"] == 0 else [f"euler_characteristic: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.euler_characteristic"] else [f"policy_violations {test.get('policy_violations')!r}"])
