NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 03: explicit loops over the points, accumulating one point at a time.'
SOLUTIONS = {
    "centroid": r'''import numpy as np


def centroid(P, w=None):
    """The weighted mean of a point set.

    Parameters
    ----------
    P : (k, d) array_like of float
        Points.
    w : (k,) array_like of float, optional
        Non-negative weights, not all zero; all ones by default.

    Returns
    -------
    p_bar : (d,) numpy.ndarray
        ``Σ w_i p_i / Σ w_i``.
    """
    P = np.array(P, dtype=float)
    k = P.shape[0]
    if w is None:
        w = np.ones(k)
    w = np.array(w, dtype=float)
    acc = np.zeros(P.shape[1])
    wsum = 0.0
    for i in range(k):
        acc += w[i] * P[i]
        wsum += w[i]
    return acc / wsum
''',
    "covariance_matrix": r'''import numpy as np


def covariance_matrix(P, Q, w=None):
    """The weighted covariance ``S = Σ w_i (p_i - p̄)(q_i - q̄)ᵀ`` of two corresponding point sets.

    Parameters
    ----------
    P, Q : (k, d) array_like of float
        Source and target points, row ``i`` of ``P`` corresponding to row ``i`` of ``Q``.
    w : (k,) array_like of float, optional
        Non-negative weights; all ones by default. ``p̄`` and ``q̄`` are the weighted centroids.

    Returns
    -------
    S : (d, d) numpy.ndarray
    """
    P = np.array(P, dtype=float)
    Q = np.array(Q, dtype=float)
    k, d = P.shape
    if w is None:
        w = np.ones(k)
    w = np.array(w, dtype=float)
    pbar = centroid(P, w)
    qbar = centroid(Q, w)
    S = np.zeros((d, d))
    for i in range(k):
        S += w[i] * np.outer(P[i] - pbar, Q[i] - qbar)
    return S
''',
    "optimal_orthogonal": r'''import numpy as np


def optimal_orthogonal(S):
    """The orthogonal matrix maximizing ``tr(R S)`` (it may be a reflection).

    Parameters
    ----------
    S : (d, d) array_like of float
        A covariance matrix, ``S = Ũ Σ Ṽᵀ`` its SVD.

    Returns
    -------
    R : (d, d) numpy.ndarray
        ``R = Ṽ Ũᵀ``.
    """
    u, sig, vt = np.linalg.svd(np.array(S, dtype=float))
    v = vt.T
    R = v.dot(u.T)
    return R
''',
    "orthogonal_align": r'''def orthogonal_align(P, Q, w=None):
    """The orthogonal map and translation that best move ``P`` onto ``Q``.

    Parameters
    ----------
    P, Q : (k, d) array_like of float
        Corresponding source and target points.
    w : (k,) array_like of float, optional
        Non-negative weights; all ones by default.

    Returns
    -------
    R : (d, d) numpy.ndarray
        Orthogonal (possibly a reflection).
    t : (d,) numpy.ndarray
        Together minimizing ``Σ w_i ‖R p_i + t - q_i‖²``.
    """
    S = covariance_matrix(P, Q, w)
    R = optimal_orthogonal(S)
    pbar = centroid(P, w)
    qbar = centroid(Q, w)
    t = qbar - R.dot(pbar)
    return R, t
''',
}
LOSES = set()
