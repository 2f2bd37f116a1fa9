NOTEBOOK = "03_arap"
DESCRIPTION = "arap_covariances() accumulates e' eᵀ (deformed edge first), the transpose of each S_i"
SOLUTIONS = {
    "arap_covariances": '''import numpy as np


def arap_covariances(V, U, F, C):
    V, U, F, C = np.asarray(V, float), np.asarray(U, float), np.asarray(F), np.asarray(C, float)
    n, d = V.shape
    S = np.zeros((n, d, d))
    for k in range(3):
        i, j = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        e, e_def = V[i] - V[j], U[i] - U[j]
        T = C[:, k, None, None] * e_def[:, :, None] * e[:, None, :]
        for corner in range(3):
            np.add.at(S, F[:, corner], T)
    return S
''',
}
# the reference local step calls arap_covariances; arap_solve builds its own operator
# the notebook's arap_solve calls the student's own local step, as a student's would
LOSES = {"arap_covariances"}
