NOTEBOOK = "01_shape_matching"
DESCRIPTION = "covariance_matrix() forgets to subtract the centroids: S = Σ w p qᵀ"
SOLUTIONS = {
    "covariance_matrix": '''import numpy as np


def covariance_matrix(P, Q, w=None):
    P = np.asarray(P, dtype=float)
    Q = np.asarray(Q, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    return P.T @ (w[:, None] * Q)
''',
}
LOSES = {"covariance_matrix"}
