NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs_matrix() lays out each handle's block as [1; v] instead of [v; 1]"
SOLUTIONS = {
    "lbs_matrix": '''import numpy as np


def lbs_matrix(V, W):
    V, W = np.asarray(V, float), np.asarray(W, float)
    V_h = np.hstack([np.ones((len(V), 1)), V])
    return (W[:, :, None] * V_h[:, None, :]).reshape(len(V), -1)
''',
}
LOSES = {"lbs_matrix"}
