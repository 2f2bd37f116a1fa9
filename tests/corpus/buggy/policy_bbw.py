NOTEBOOK = "04_bbw"
DESCRIPTION = "bbw() is igl.bbw, then rows normalized"
SOLUTIONS = {
    "bbw": '''import igl
import numpy as np


def bbw(V, F, b, bc):
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    W = igl.bbw(V, F, np.asarray(b, dtype=np.int64), np.asarray(bc, dtype=float))
    W = np.clip(W, 0.0, 1.0)
    return W / W.sum(axis=1, keepdims=True)
''',
}
LOSES = {"bbw"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "bbw")
    problems = [] if "igl.bbw" in test["summary"] and test["score"] == 0 else [f"bbw: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.bbw"] else [f"policy_violations {test.get('policy_violations')!r}"])
