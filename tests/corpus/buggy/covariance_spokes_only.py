NOTEBOOK = "03_arap"
DESCRIPTION = "arap_covariances() sums only the spokes (edges at vertex i) of each triangle, not the rim opposite i"
SOLUTIONS = {
    "arap_covariances": '''import numpy as np


def arap_covariances(V, U, F, C):
    V, U, F, C = np.asarray(V, float), np.asarray(U, float), np.asarray(F), np.asarray(C, float)
    n, d = V.shape
    S = np.zeros((n, d, d))
    for k in range(3):
        i, j = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        T = C[:, k, None, None] * (V[i] - V[j])[:, :, None] * (U[i] - U[j])[:, None, :]
        # the edge opposite corner k touches only its own two end points
        np.add.at(S, i, T)
        np.add.at(S, j, T)
    return S
''',
}
# the notebook's arap_solve calls the student's own local step, as a student's would
LOSES = {"arap_covariances"}
