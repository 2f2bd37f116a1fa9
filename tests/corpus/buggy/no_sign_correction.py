NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() is the SVD answer without the sign fix: reflections (det -1) come back"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


def optimal_rotation(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, dtype=float))
    return np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)
''',
}
LOSES = {"optimal_rotation"}
