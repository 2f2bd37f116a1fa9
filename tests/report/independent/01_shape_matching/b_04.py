NOTEBOOK = "01_shape_matching"
DESCRIPTION = "one big function per cell with nested helper closures (_as_array, _weights, _center)"
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
    def _weights(k):
        if w is None:
            return np.ones(k)
        return np.asarray(w, dtype=float)

    pts = np.asarray(P, dtype=float)
    ww = _weights(pts.shape[0])
    total = ww.sum()
    return (pts * ww[:, np.newaxis]).sum(axis=0) / total
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
    def _as_array(X):
        return np.asarray(X, dtype=float)

    def _weights(k):
        return np.ones(k) if w is None else _as_array(w)

    def _center(X, ww):
        return X - centroid(X, ww)

    src, dst = _as_array(P), _as_array(Q)
    ww = _weights(src.shape[0])
    a = _center(src, ww)
    b = _center(dst, ww)
    return (a * ww[:, np.newaxis]).T @ b
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
    def _svd(M):
        left, values, right_t = np.linalg.svd(M)
        return left, values, right_t.T

    left, _, right = _svd(np.asarray(S, dtype=float))
    return right @ left.T
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
    def _translation(R):
        return centroid(Q, w) - R @ centroid(P, w)

    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    return R, _translation(R)
''',
}
LOSES = set()
