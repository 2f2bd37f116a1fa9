NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs_matrix() puts 1 instead of w_ij in each handle's translation column: every handle's translation moves every vertex"
SOLUTIONS = {
    "lbs_matrix": '''import numpy as np


def lbs_matrix(V, W):
    V, W = np.asarray(V, float), np.asarray(W, float)
    n, m = W.shape
    M = W[:, :, None] * np.hstack([V, np.ones((n, 1))])[:, None, :]
    M[:, :, -1] = 1.0
    return M.reshape(n, -1)
''',
}
LOSES = {"lbs_matrix"}
