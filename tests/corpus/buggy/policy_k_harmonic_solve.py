NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_solve() hands Q and the handles to igl.min_quad_with_fixed, which computes its answer"
SOLUTIONS = {
    "k_harmonic_solve": '''import igl
import numpy as np
import scipy.sparse as sp


def k_harmonic_solve(data, handle_displacements):
    D_h = np.asarray(handle_displacements, dtype=float)
    # min_quad_with_fixed eliminates the handles itself: the whole solve in one library call
    return igl.min_quad_with_fixed(sp.csc_matrix(data["Q"]), np.zeros((data["n"], D_h.shape[1])),
                                   np.asarray(data["handles"], dtype=np.int64), D_h)
''',
    "k_harmonic_precompute": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def k_harmonic_precompute(Q, handles):
    Q = sp.csr_matrix(Q, dtype=float)
    n = Q.shape[0]
    handles = np.asarray(handles)
    if handles.ndim != 1 or len(handles) == 0:
        raise ValueError("handles must list at least one vertex")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handles must be vertices 0..{n - 1}")
    if len(np.unique(handles)) < len(handles):
        raise ValueError("handles repeats a vertex")
    free = np.setdiff1d(np.arange(n), handles)
    return {"n": n, "handles": handles, "free": free, "Q": Q, "solve_ff": None}
''',
}
# the call is charged once, to the solve that made it; the precompute's object (the student's design, Q kept
# whole) serves that solve correctly
LOSES = {"k_harmonic_solve"}


def CHECK(result, autograded, params):
    """The solve scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "k_harmonic_solve")
    problems = [] if "igl.min_quad_with_fixed" in test["summary"] and test["score"] == 0 else [f"k_harmonic_solve: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.min_quad_with_fixed"] else [f"policy_violations {test.get('policy_violations')!r}"])
