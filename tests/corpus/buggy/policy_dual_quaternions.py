NOTEBOOK = "05_lbs"
DESCRIPTION = "dual_quaternions() by scipy's RigidTransform.as_dual_quat (dqs calls it: only dual_quaternions loses)"
SOLUTIONS = {
    "dual_quaternions": '''import numpy as np
from scipy.spatial.transform import RigidTransform


def dual_quaternions(T):
    T = np.asarray(T, dtype=float)
    for j, R in enumerate(T[:, :, :3]):
        if not (np.allclose(R.T @ R, np.eye(3), atol=1e-6) and np.isclose(np.linalg.det(R), 1.0, atol=1e-6)):
            raise ValueError(f"T[{j}] is not a rigid transform: its 3x3 part is not a rotation")
    M = np.tile(np.eye(4), (len(T), 1, 1))
    M[:, :3, :] = T
    return RigidTransform.from_matrix(M).as_dual_quat(scalar_first=True).reshape(-1, 2, 4)
''',
}
LOSES = {"dual_quaternions"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "dual_quaternions")
    problems = [] if "scipy.spatial.transform.RigidTransform.as_dual_quat" in test["summary"] and test["score"] == 0 else [f"dual_quaternions: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["scipy.spatial.transform.RigidTransform.as_dual_quat"] else [f"policy_violations {test.get('policy_violations')!r}"])
