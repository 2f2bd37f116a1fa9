NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() by getattr(scipy.linalg, 'po' + 'lar'), the SVD only to flip a reflection (rigid_align calls it: only optimal_rotation loses)"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np
import scipy.linalg


def optimal_rotation(S):
    S = np.asarray(S, dtype=float)
    d = S.shape[-1]
    A = S.reshape(-1, d, d)
    nearest = getattr(scipy.linalg, "po" + "lar")  # the orthogonal factor of Sᵀ maximizes tr(R S)
    R = np.stack([nearest(a.T)[0] for a in A])
    flip = np.linalg.det(R) < 0
    if flip.any():  # a reflection: flip the direction of the smallest singular value
        U, _, Vt = np.linalg.svd(A[flip])
        W = np.swapaxes(Vt, 1, 2)
        W[:, :, -1] *= -1
        R[flip] = W @ np.swapaxes(U, 1, 2)
    return R.reshape(S.shape)
''',
}
LOSES = {"optimal_rotation"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "optimal_rotation")
    problems = [] if "scipy.linalg.polar" in test["summary"] and test["score"] == 0 else [f"optimal_rotation: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["scipy.linalg.polar"] else [f"policy_violations {test.get('policy_violations')!r}"])
