NOTEBOOK = "03_arap"
DESCRIPTION = "cotangent_weights() is an alias of igl.cotmatrix_entries taken at import (every later function calls it: only cotangent_weights loses)"
SOLUTIONS = {
    "cotangent_weights": '''import numpy as np
from igl import cotmatrix_entries as _entries


def cotangent_weights(V, F):
    return _entries(np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64))
''',
}
LOSES = {"cotangent_weights"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "cotangent_weights")
    problems = [] if "igl.cotmatrix_entries" in test["summary"] and test["score"] == 0 else [f"cotangent_weights: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.cotmatrix_entries"] else [f"policy_violations {test.get('policy_violations')!r}"])
