NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() flips the smallest singular vector where det(S) < 0 instead of where det(Ũ Vᵀ) = -1: a singular S (det 0) is never corrected"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


def optimal_rotation(S):
    S = np.asarray(S, dtype=float)
    U, _, Vt = np.linalg.svd(S)
    V = np.swapaxes(Vt, -1, -2).copy()
    V[..., -1] *= np.where(np.linalg.det(S) < 0, -1.0, 1.0)[..., None]
    return V @ np.swapaxes(U, -1, -2)
''',
}
LOSES = {"optimal_rotation"}
