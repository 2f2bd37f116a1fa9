NOTEBOOK = "01_shape_matching"
DESCRIPTION = "optimal_orthogonal() through a module-level alias of scipy.linalg.orthogonal_procrustes (orthogonal_align calls it: only optimal_orthogonal loses)"
SOLUTIONS = {
    "optimal_orthogonal": '''import numpy as np
from scipy.linalg import orthogonal_procrustes as _fit


def optimal_orthogonal(S):
    S = np.asarray(S, dtype=float)
    return _fit(np.eye(len(S)), S.T)[0]
''',
}
LOSES = {"optimal_orthogonal"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "optimal_orthogonal")
    problems = [] if "scipy.linalg.orthogonal_procrustes" in test["summary"] and test["score"] == 0 else [f"optimal_orthogonal: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["scipy.linalg.orthogonal_procrustes"] else [f"policy_violations {test.get('policy_violations')!r}"])
