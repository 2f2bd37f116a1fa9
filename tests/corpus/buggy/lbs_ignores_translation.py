NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs() blends only the linear parts A_j v and drops the translations t_j"
SOLUTIONS = {
    "lbs": '''import numpy as np


def lbs(V, W, T):
    V, W, T = np.asarray(V, float), np.asarray(W, float), np.asarray(T, float)
    d = V.shape[1]
    return np.einsum("ij,jab,ib->ia", W, T[:, :, :d], V)
''',
}
LOSES = {"lbs"}
