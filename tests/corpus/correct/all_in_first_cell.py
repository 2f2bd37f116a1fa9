NOTEBOOK = "01_shape_matching"
DESCRIPTION = "every function and two helpers in the first solution cell; the other solution cells hold only a comment"
SOLUTIONS = {
    "centroid": '''import numpy as np


def _weights(w, k):
    return np.ones(k) if w is None else np.asarray(w, dtype=float)


def _centred(P, w):
    return P - centroid(P, w)


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = _weights(w, len(P))
    return np.sum(w[:, None] * P, axis=0) / np.sum(w)


def covariance_matrix(P, Q, w=None):
    P, Q = np.asarray(P, dtype=float), np.asarray(Q, dtype=float)
    w = _weights(w, len(P))
    return np.einsum("i,ia,ib->ab", w, _centred(P, w), _centred(Q, w))


def optimal_orthogonal(S):
    U, _, Vt = np.linalg.svd(S)
    return (U @ Vt).T


def orthogonal_align(P, Q, w=None):
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    return R, centroid(Q, w) - R @ centroid(P, w)
''',
    "covariance_matrix": "# written in the first cell\n",
    "optimal_orthogonal": "# written in the first cell\n",
    "orthogonal_align": "# written in the first cell\n",
}
LOSES = set()
