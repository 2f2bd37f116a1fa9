from tests.corpus import teaching_cell

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
    # the student's design keeps Q whole for the library call
    "k_harmonic_precompute": teaching_cell(NOTEBOOK, "k_harmonic_precompute").replace(
        '"Q_fh": Q[free][:, handles],\n        "solve_ff": spla.factorized(Q[free][:, free].tocsc()) if len(free) else None,',
        '"Q": Q,',
    ),
}
# the call is charged once, to the solve that made it; the precompute's object (the student's design, Q kept
# whole) serves that solve correctly
LOSES = {"k_harmonic_solve"}


def CHECK(result, autograded, params):
    """The solve scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "k_harmonic_solve")
    problems = [] if "igl.min_quad_with_fixed" in test["summary"] and test["score"] == 0 else [f"k_harmonic_solve: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.min_quad_with_fixed"] else [f"policy_violations {test.get('policy_violations')!r}"])
