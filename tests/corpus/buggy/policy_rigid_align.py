NOTEBOOK = "02_sign_correction"
DESCRIPTION = "rigid_align() by scipy's Rotation.align_vectors in 3D"
SOLUTIONS = {
    "rigid_align": '''import numpy as np
from scipy.spatial.transform import Rotation


def rigid_align(P, Q, w=None):
    P, Q = np.asarray(P, dtype=float), np.asarray(Q, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    p, q = centroid(P, w), centroid(Q, w)
    if P.shape[1] == 3:
        R = Rotation.align_vectors(Q - q, P - p, weights=w)[0].as_matrix()
    else:
        R = optimal_rotation(covariance_matrix(P, Q, w))
    return R, q - R @ p
''',
}
LOSES = {"rigid_align"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "rigid_align")
    problems = [] if "scipy.spatial.transform.Rotation.align_vectors" in test["summary"] and test["score"] == 0 else [f"rigid_align: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["scipy.spatial.transform.Rotation.align_vectors"] else [f"policy_violations {test.get('policy_violations')!r}"])
