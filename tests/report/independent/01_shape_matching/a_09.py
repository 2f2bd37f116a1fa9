NOTEBOOK = '01_shape_matching'
DESCRIPTION = '09 module style with many tiny private functions (_arr, _ones, _wsum, _svd ...)'
SOLUTIONS = {
    'centroid': r'''import numpy as np


def _arr(X):
    return np.asarray(X, dtype=float)


def _ones_if_none(w, k):
    return np.ones(k) if w is None else _arr(w)


def _wsum(X, w):
    return np.tensordot(w, X, axes=1)


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
    P = _arr(P)
    w = _ones_if_none(w, len(P))
    return _wsum(P, w) / np.sum(w)
''',
    'covariance_matrix': r'''import numpy as np


def _centre(X, w):
    return X - centroid(X, w)


def _outer_sum(A, B, w):
    return np.tensordot(A * w[:, None], B, axes=(0, 0))


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
    P, Q = _arr(P), _arr(Q)
    w = _ones_if_none(w, len(P))
    return _outer_sum(_centre(P, w), _centre(Q, w), w)
''',
    'optimal_orthogonal': r'''import numpy as np


def _svd(S):
    return np.linalg.svd(_arr(S))


def _T(A):
    return np.swapaxes(A, -1, -2)


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
    u, _, vt = _svd(S)
    return _T(vt) @ _T(u)
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    return R, _translation(R, P, Q, w)


def _translation(R, P, Q, w):
    return centroid(Q, w) - R @ centroid(P, w)
''',
}
LOSES = set()
