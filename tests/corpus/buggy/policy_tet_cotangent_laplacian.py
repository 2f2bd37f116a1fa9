NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_cotangent_laplacian() is igl.cotmatrix on tetrahedra"
SOLUTIONS = {
    "tet_cotangent_laplacian": '''import igl
import numpy as np


def tet_cotangent_laplacian(V, T):
    return igl.cotmatrix(np.asarray(V, dtype=float), np.asarray(T, dtype=np.int64))
''',
}
LOSES = {"tet_cotangent_laplacian"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "tet_cotangent_laplacian")
    problems = [] if "igl.cotmatrix" in test["summary"] and test["score"] == 0 else [f"tet_cotangent_laplacian: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.cotmatrix"] else [f"policy_violations {test.get('policy_violations')!r}"])
