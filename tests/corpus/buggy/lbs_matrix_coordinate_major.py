NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs_matrix() lays its columns out coordinate by coordinate (reshaped from (n, d+1, m)) instead of handle by handle"
SOLUTIONS = {
    "lbs_matrix": '''import numpy as np


def lbs_matrix(V, W):
    V, W = np.asarray(V, float), np.asarray(W, float)
    V_h = np.hstack([V, np.ones((len(V), 1))])
    return (V_h[:, :, None] * W[:, None, :]).reshape(len(V), -1)
''',
}
LOSES = {"lbs_matrix"}
