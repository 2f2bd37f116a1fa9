NOTEBOOK = "05_lbs"
DESCRIPTION = "dual_quaternion_transforms() builds R with the sign of the 2w[v]x term flipped (the rotation of the conjugate); dqs() inherits it"
SOLUTIONS = {
    "dual_quaternion_transforms": '''import numpy as np


def dual_quaternion_transforms(Q):
    Q = np.asarray(Q, dtype=float)
    T = np.zeros((len(Q), 3, 4))
    for k, (q0, qe) in enumerate(Q):
        c0, ce = q0 / np.linalg.norm(q0), qe / np.linalg.norm(q0)
        w, v, we, ve = c0[0], c0[1:], ce[0], ce[1:]
        cross = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
        T[k, :, :3] = (w * w - v @ v) * np.eye(3) + 2 * np.outer(v, v) - 2 * w * cross
        T[k, :, 3] = 2 * (w * ve - we * v + np.cross(v, ve))
    return T
''',
}
# dqs calls the student's dual_quaternion_transforms and is judged with its outputs: a bug is charged once
LOSES = {"dual_quaternion_transforms"}
