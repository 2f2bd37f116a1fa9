NOTEBOOK = "05_lbs"
DESCRIPTION = "dual_quaternions() never checks that R_j is a rotation: a scaled or mirrored 3x3 part gets a quaternion instead of the contract's ValueError"
SOLUTIONS = {
    "dual_quaternions": '''import numpy as np


def dual_quaternions(T):
    T = np.asarray(T, dtype=float)
    Q = np.zeros((len(T), 2, 4))
    for j, (R, t) in enumerate(zip(T[:, :, :3], T[:, :, 3])):
        tr = np.trace(R)
        # P[a, b] = 4 q_a q_b for q = (w, x, y, z): the identities between R and q
        P = np.array([
            [1 + tr, R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]],
            [R[2, 1] - R[1, 2], 1 + 2 * R[0, 0] - tr, R[0, 1] + R[1, 0], R[0, 2] + R[2, 0]],
            [R[0, 2] - R[2, 0], R[0, 1] + R[1, 0], 1 + 2 * R[1, 1] - tr, R[1, 2] + R[2, 1]],
            [R[1, 0] - R[0, 1], R[0, 2] + R[2, 0], R[1, 2] + R[2, 1], 1 + 2 * R[2, 2] - tr],
        ])
        k = np.argmax(np.diag(P))  # the largest |q_k|
        q = P[k] / np.sqrt(4 * P[k, k])  # 4 q_k q_b / (4 |q_k|) = ±q_b
        w, v = q[0], q[1:]
        Q[j, 0] = q
        Q[j, 1] = 0.5 * np.r_[-t @ v, w * t + np.cross(t, v)]  # ½ (0, t) q
    return Q
''',
}
LOSES = {"dual_quaternions"}
