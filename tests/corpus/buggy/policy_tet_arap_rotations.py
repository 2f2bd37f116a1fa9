NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_arap_rotations() by scipy's polar decomposition, the SVD only for reflections"
SOLUTIONS = {
    "tet_arap_rotations": '''import numpy as np
from scipy.linalg import polar


def tet_arap_rotations(V, U, T):
    J = deformation_gradients(V, U, T)
    R = np.stack([polar(j)[0] for j in J])
    bad = np.linalg.det(R) < 0
    X, _, Yt = np.linalg.svd(J[bad])
    X[:, :, 2] *= -1
    R[bad] = X @ Yt
    return R
''',
}
LOSES = {"tet_arap_rotations"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "tet_arap_rotations")
    problems = [] if "scipy.linalg.polar" in test["summary"] and test["score"] == 0 else [f"tet_arap_rotations: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["scipy.linalg.polar"] else [f"policy_violations {test.get('policy_violations')!r}"])
