NOTEBOOK = "00_meshes"
DESCRIPTION = "edges() returns the right rows as float64, which cannot index V (the contract asks for int)"
SOLUTIONS = {
    "edges": '''import numpy as np


def edges(F):
    F = np.asarray(F, dtype=float)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return np.unique(E, axis=0)
''',
}
LOSES = {"edges"}
