NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_volumes() returns |det| / 6: every volume positive, the orientation lost"
SOLUTIONS = {
    "tet_volumes": '''import numpy as np


def tet_volumes(V, T):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    return np.abs(np.linalg.det(D)) / 6
''',
}
LOSES = {"tet_volumes"}
