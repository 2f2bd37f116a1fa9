NOTEBOOK = "01_shape_matching"
DESCRIPTION = "student coming from MATLAB: explicit sum / sum(w), repmat-like broadcasting, [U,S,V] = svd naming"
SOLUTIONS = {
    "centroid": '''import numpy as np


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
    w = np.array(w, dtype=float).reshape(k, 1)   # column vector like in matlab
    p_bar = np.sum(w * P, axis=0) / np.sum(w)
    return p_bar
''',
    "covariance_matrix": '''import numpy as np


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
    pc = P - centroid(P, w)
    qc = Q - centroid(Q, w)
    # S = Pc' * diag(w) * Qc, but without diag
    S = np.zeros((d, d))
    for a in range(d):
        for b in range(d):
            S[a, b] = np.sum(w * pc[:, a] * qc[:, b])
    return S
''',
    "optimal_orthogonal": '''import numpy as np


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
    S = np.array(S, dtype=float)
    # matlab: [U, Sig, V] = svd(S) gives V directly, numpy gives V' (Vt)
    U, sig, Vt = np.linalg.svd(S)
    V = Vt.T
    R = V @ U.T
    return R
''',
    "orthogonal_align": '''import numpy as np


def orthogonal_align(P, Q, w=None):
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
    t = qbar - R @ pbar
    return R, t
''',
}
LOSES = set()
