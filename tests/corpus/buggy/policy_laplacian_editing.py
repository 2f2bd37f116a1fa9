NOTEBOOK = "03b_arap_global"
DESCRIPTION = "laplacian_editing() eliminates the handles with igl.min_quad_with_fixed instead of the global step it builds on"
SOLUTIONS = {
    "laplacian_editing": '''import igl
import numpy as np
import scipy.sparse as sp


def laplacian_editing(V, F, handles, handle_positions):
    V = np.asarray(V, dtype=float)
    L = sp.csc_matrix(cotangent_laplacian(V, F))
    # the global step with every R_i = I solves L U = L V: minimize ½ Uᵀ(-L)U + Uᵀ(L V), handles fixed
    known = np.asarray(handles, dtype=np.int64)
    return igl.min_quad_with_fixed((-L).tocsc(), np.asarray(L @ V), known, np.asarray(handle_positions, dtype=float))
''',
}
LOSES = {"laplacian_editing"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "laplacian_editing")
    problems = [] if "igl.min_quad_with_fixed" in test["summary"] and test["score"] == 0 else [f"laplacian_editing: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.min_quad_with_fixed"] else [f"policy_violations {test.get('policy_violations')!r}"])
