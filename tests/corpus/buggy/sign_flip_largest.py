NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() fixes the sign by flipping the singular vector of the LARGEST singular value"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


def optimal_rotation(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, dtype=float))
    D = np.ones(U.shape[:-1])
    # numpy sorts singular values in decreasing order: index 0 is the largest
    D[..., 0] = np.linalg.det(U @ Vt)
    return np.swapaxes(Vt, -1, -2) @ (D[..., :, None] * np.swapaxes(U, -1, -2))
''',
}
LOSES = {"optimal_rotation"}
