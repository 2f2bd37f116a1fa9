NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 05: normalizes inputs through small helper functions (_as_float, _as_int, _weights) defined at the top of each cell.'
SOLUTIONS = {
    "centroid": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _weights(w, k):
    if w is None:
        return np.ones(k, dtype=np.float64)
    return _as_float(w).reshape(k)


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
    P = _as_float(P)
    w = _weights(w, P.shape[0])
    return P.T @ w / w.sum()
''',
    "covariance_matrix": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _weights(w, k):
    if w is None:
        return np.ones(k, dtype=np.float64)
    return _as_float(w).reshape(k)


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
    P, Q = _as_float(P), _as_float(Q)
    w = _weights(w, P.shape[0])
    Pc = P - centroid(P, w)
    Qc = Q - centroid(Q, w)
    return Pc.T @ (Qc * w[:, None])
''',
    "optimal_orthogonal": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


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
    S = _as_float(S)
    Ut, sv, Vt = np.linalg.svd(S)
    return np.matmul(Vt.T, Ut.T)
''',
    "orthogonal_align": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


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
    P, Q = _as_float(P), _as_float(Q)
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    t = centroid(Q, w) - np.matmul(R, centroid(P, w))
    return R, t
''',
}
LOSES = set()
