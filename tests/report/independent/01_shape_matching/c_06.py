NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 06: library-minded student, relies on numpy routines (np.dot, np.sum with keepdims, full_matrices) and checks shapes.'
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
    X = np.asarray(P, dtype=float)
    if w is None:
        return X.mean(axis=0)
    weights = np.asarray(w, dtype=float)
    return np.dot(weights, X) / weights.sum()
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
    X = np.asarray(P, dtype=float)
    Y = np.asarray(Q, dtype=float)
    assert X.shape == Y.shape
    weights = np.ones(len(X)) if w is None else np.asarray(w, dtype=float)
    Xc = X - centroid(X, weights)
    Yc = Y - centroid(Y, weights)
    return np.dot(Xc.T * weights, Yc)
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
    U_, s_, VT_ = np.linalg.svd(np.asarray(S, dtype=float), full_matrices=True)
    return np.dot(VT_.T, U_.T)
''',
    "orthogonal_align": r'''import numpy as np


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
    t = centroid(Q, w) - np.dot(R, centroid(P, w))
    return R, t
''',
}
LOSES = set()
