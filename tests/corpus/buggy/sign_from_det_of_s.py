NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() sets D = diag(1, ..., det S) instead of the sign of det(Ũ Uᵀ): not a rotation when S is singular"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


def optimal_rotation(S):
    S = np.asarray(S, dtype=float)
    U, _, Vt = np.linalg.svd(S)
    D = np.ones(U.shape[:-1])
    D[..., -1] = np.linalg.det(S)
    D[..., -1] /= np.abs(np.where(D[..., -1] == 0, 1.0, D[..., -1]))
    return np.swapaxes(Vt, -1, -2) @ (D[..., :, None] * np.swapaxes(U, -1, -2))
''',
}
LOSES = {"optimal_rotation"}
