NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() by Horn's quaternion method in 3D (eigenvector of a 4x4 matrix) and atan2 in 2D"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


def optimal_rotation(S):
    S = np.asarray(S, dtype=float)
    d = S.shape[-1]
    A = S.reshape(-1, d, d)
    if d == 2:
        theta = np.arctan2(A[:, 0, 1] - A[:, 1, 0], A[:, 0, 0] + A[:, 1, 1])
        c, s = np.cos(theta), np.sin(theta)
        return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2).reshape(S.shape)
    # tr(R(q) S) = qᵀ N q for the rotation R(q) of a unit quaternion q = (w, x, y, z),
    # N Horn's symmetric 4x4 matrix of S: the best q is N's top eigenvector
    M = A
    Sxx, Sxy, Sxz = M[:, 0, 0], M[:, 0, 1], M[:, 0, 2]
    Syx, Syy, Syz = M[:, 1, 0], M[:, 1, 1], M[:, 1, 2]
    Szx, Szy, Szz = M[:, 2, 0], M[:, 2, 1], M[:, 2, 2]
    N = np.empty((len(M), 4, 4))
    N[:, 0] = np.stack([Sxx + Syy + Szz, Syz - Szy, Szx - Sxz, Sxy - Syx], -1)
    N[:, 1] = np.stack([Syz - Szy, Sxx - Syy - Szz, Sxy + Syx, Szx + Sxz], -1)
    N[:, 2] = np.stack([Szx - Sxz, Sxy + Syx, -Sxx + Syy - Szz, Syz + Szy], -1)
    N[:, 3] = np.stack([Sxy - Syx, Szx + Sxz, Syz + Szy, -Sxx - Syy + Szz], -1)
    _, vectors = np.linalg.eigh(N)
    w, x, y, z = np.moveaxis(vectors[:, :, -1], -1, 0)
    R = np.stack([
        np.stack([w*w + x*x - y*y - z*z, 2*(x*y - w*z), 2*(x*z + w*y)], -1),
        np.stack([2*(x*y + w*z), w*w - x*x + y*y - z*z, 2*(y*z - w*x)], -1),
        np.stack([2*(x*z - w*y), 2*(y*z + w*x), w*w - x*x - y*y + z*z], -1),
    ], -2)
    return R.reshape(S.shape)
''',
}
LOSES = set()
