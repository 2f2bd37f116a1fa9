NOTEBOOK = "01_shape_matching"
DESCRIPTION = "linear-algebra student: scipy.linalg.svd, weights as a normalized column, S assembled as a product with diag-free broadcasting"
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
    X = np.asarray(P, dtype=float)
    weights = np.full(len(X), 1.0) if w is None else np.asarray(w, dtype=float)
    return np.sum(X * (weights / np.sum(weights))[:, None], axis=0)
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
    X = np.asarray(P, dtype=float)
    Y = np.asarray(Q, dtype=float)
    weights = np.full(len(X), 1.0) if w is None else np.asarray(w, dtype=float)
    Xc = X - centroid(X, weights)
    Yc = Y - centroid(Y, weights)
    return (weights[:, None] * Xc).T.dot(Yc)
''',
    "optimal_orthogonal": '''import numpy as np
import scipy.linalg


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
    # scipy returns S = A diag(s) Bh, so R = Bh^T A^T = (A Bh)^T
    A, s, Bh = scipy.linalg.svd(np.asarray(S, dtype=float))
    return (A @ Bh).T
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
    p0 = centroid(P, w)
    q0 = centroid(Q, w)
    return R, q0 - p0 @ R.T
''',
}
LOSES = set()
