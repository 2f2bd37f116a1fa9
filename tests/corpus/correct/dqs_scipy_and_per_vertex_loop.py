NOTEBOOK = "05_lbs"
DESCRIPTION = "dual quaternions through scipy's Rotation (scalar-last, reordered), signs as scipy returns them, dqs with a loop over vertices choosing the side per handle"
SOLUTIONS = {
    "dual_quaternions": '''import numpy as np
from scipy.spatial.transform import Rotation


def dual_quaternions(T):
    T = np.asarray(T, dtype=float)
    for j in range(len(T)):  # scipy's from_matrix would quietly orthogonalize a scaled matrix
        if not np.allclose(T[j, :, :3].T @ T[j, :, :3], np.eye(3), atol=1e-6) or np.linalg.det(T[j, :, :3]) < 0:
            raise ValueError(f"T[{j}] is not a rigid transform")
    q = Rotation.from_matrix(T[:, :, :3]).as_quat()[:, [3, 0, 1, 2]]
    t = T[:, :, 3]
    w, v = q[:, 0], q[:, 1:]
    qe = 0.5 * np.c_[-np.sum(t * v, axis=1), w[:, None] * t + np.cross(t, v)]
    return np.stack([q, qe], axis=1)
''',
    "dual_quaternion_transforms": '''import numpy as np
from scipy.spatial.transform import Rotation


def dual_quaternion_transforms(Q):
    Q = np.asarray(Q, dtype=float)
    n = np.linalg.norm(Q[:, 0], axis=1)[:, None]
    c0, ce = Q[:, 0] / n, Q[:, 1] / n
    R = Rotation.from_quat(c0[:, [1, 2, 3, 0]]).as_matrix()
    conj = c0 * [1, -1, -1, -1]
    w1, v1, w2, v2 = ce[:, 0], ce[:, 1:], conj[:, 0], conj[:, 1:]
    t = 2 * (w1[:, None] * v2 + w2[:, None] * v1 + np.cross(v1, v2))
    return np.concatenate([R, t[:, :, None]], axis=2)
''',
    "dqs": '''import numpy as np


def dqs(V, W, T):
    V, W = np.asarray(V, dtype=float), np.asarray(W, dtype=float)
    Q = dual_quaternions(T)
    U = np.empty_like(V)
    for i in range(len(V)):
        b = np.zeros((2, 4))
        for j in range(len(Q)):
            sign = 1.0 if Q[j, 0] @ Q[0, 0] >= 0 else -1.0
            b += W[i, j] * sign * Q[j]
        Ti = dual_quaternion_transforms(b[None])[0]
        U[i] = Ti[:, :3] @ V[i] + Ti[:, 3]
    return U
''',
}
LOSES = set()
