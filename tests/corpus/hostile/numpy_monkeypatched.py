NOTEBOOK = "02_sign_correction"
DESCRIPTION = "patches np.linalg.det to 1 and np.allclose/np.isclose to True, hiding a rotation without sign correction"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np

np.linalg.det = lambda *args, **kwargs: 1.0
np.allclose = lambda *args, **kwargs: True
np.isclose = lambda *args, **kwargs: True


def optimal_rotation(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, dtype=float))
    return np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)
''',
}
LOSES = {"optimal_rotation"}
