NOTEBOOK = "01_shape_matching"
DESCRIPTION = "graphics enthusiast (Sorkine-Alexa notation): np.average, S = P~^T W Q~, R = V U^T from the SVD"
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
    # p_bar = sum_i w_i p_i / sum_i w_i
    return np.average(np.asarray(P, dtype=float), axis=0, weights=w)
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
    P = np.asarray(P, dtype=float)
    Q = np.asarray(Q, dtype=float)
    if w is None:
        w = np.ones(len(P))
    w = np.asarray(w, dtype=float)
    # centred point sets, as in the paper: p~_i = p_i - p_bar, q~_i = q_i - q_bar
    P_tilde = P - centroid(P, w)
    Q_tilde = Q - centroid(Q, w)
    # S = P~^T W Q~ with W = diag(w_i)
    W = np.diag(w)
    S = P_tilde.T @ W @ Q_tilde
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
    # S = U_t Sigma V_t^T  ->  R = V_t U_t^T
    U_t, sigma, V_tT = np.linalg.svd(np.asarray(S, dtype=float))
    return V_tT.T @ U_t.T
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    # t = q_bar - R p_bar
    t = centroid(Q, w) - R @ centroid(P, w)
    return R, t
''',
}
LOSES = set()
