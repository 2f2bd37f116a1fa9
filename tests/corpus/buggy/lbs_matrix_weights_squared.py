NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs_matrix() applies the weights twice: each block is w_ij²·[v_i; 1]"
SOLUTIONS = {
    "lbs_matrix": '''import numpy as np


def lbs_matrix(V, W):
    V, W = np.asarray(V, float), np.asarray(W, float)
    V_h = np.hstack([V, np.ones((len(V), 1))])
    weighted = W[:, :, None] * V_h[:, None, :]
    return (W[:, :, None] * weighted).reshape(len(V), -1)
''',
}
LOSES = {"lbs_matrix"}
