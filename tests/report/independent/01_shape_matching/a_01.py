NOTEBOOK = '01_shape_matching'
DESCRIPTION = '01 maths undergraduate: careful, small documented helpers, normalized weights, SVD via a helper'
SOLUTIONS = {
    'centroid': r'''import numpy as np


def _as_weights(w, k):
    """Turn the optional weights into a float vector of length k (ones if missing)."""
    if w is None:
        return np.ones(k)
    return np.asarray(w, dtype=float).reshape(k)


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
    P = np.asarray(P, dtype=float)
    weights = _as_weights(w, P.shape[0])
    # sum_i w_i p_i divided by the total weight (a convex combination of the points)
    total_weight = weights.sum()
    return (weights @ P) / total_weight
''',
    'covariance_matrix': r'''import numpy as np


def _centred(X, weights):
    """X with its weighted centroid subtracted from every row."""
    return X - centroid(X, weights)


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
    weights = np.ones(P.shape[0]) if w is None else np.asarray(w, dtype=float)
    P_tilde = _centred(P, weights)
    Q_tilde = _centred(Q, weights)
    # S = P~^T diag(w) Q~, the diagonal applied to the rows of Q~
    return P_tilde.T @ (weights[:, np.newaxis] * Q_tilde)
''',
    'optimal_orthogonal': r'''import numpy as np


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
    S = np.asarray(S, dtype=float)
    # numpy gives S = U diag(sigma) Vt, so Vt is already the transpose of V~
    U_svd, sigma, Vt_svd = np.linalg.svd(S)
    # V~ U~^T is the transpose of U~ V~^T = U_svd @ Vt_svd
    return (U_svd @ Vt_svd).T
''',
    'orthogonal_align': r'''def orthogonal_align(P, Q, w=None):
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
    p_bar, q_bar = centroid(P, w), centroid(Q, w)
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    # for this R the translation has to carry p_bar onto q_bar
    return R, q_bar - R @ p_bar
''',
}
LOSES = set()
