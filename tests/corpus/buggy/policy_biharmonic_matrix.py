NOTEBOOK = "04_bbw"
DESCRIPTION = "biharmonic_matrix() from igl.cotmatrix, called in a helper it wrote, and igl.massmatrix (allowed there)"
SOLUTIONS = {
    "biharmonic_matrix": '''import igl
import numpy as np
import scipy.sparse as sp


def _laplacian(V, F):
    return igl.cotmatrix(V, F)


def biharmonic_matrix(V, F):
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    L = sp.csr_matrix(_laplacian(V, F))
    M = igl.massmatrix(V, F)
    return (L @ sp.diags(1.0 / M.diagonal()) @ L).tocsr()
''',
}
LOSES = {"biharmonic_matrix"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "biharmonic_matrix")
    problems = [] if "igl.cotmatrix" in test["summary"] and test["score"] == 0 else [f"biharmonic_matrix: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.cotmatrix"] else [f"policy_violations {test.get('policy_violations')!r}"])
