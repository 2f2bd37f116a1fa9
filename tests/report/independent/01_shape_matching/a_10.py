NOTEBOOK = '01_shape_matching'
DESCRIPTION = '10 careful validator: checks shapes, weights and finiteness, raising ValueError with messages'
SOLUTIONS = {
    'centroid': r'''import numpy as np


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
    if P.ndim != 2:
        raise ValueError(f"P must be a (k, d) array, got shape {P.shape}")
    if P.shape[0] == 0:
        raise ValueError("P must contain at least one point")
    if w is None:
        w = np.ones(P.shape[0])
    else:
        w = np.asarray(w, dtype=float)
        if w.shape != (P.shape[0],):
            raise ValueError(f"w must have shape ({P.shape[0]},), got {w.shape}")
        if np.any(w < 0):
            raise ValueError("weights must be non-negative")
    total = w.sum()
    if total <= 0:
        raise ValueError("the weights must not all be zero")
    return (w / total) @ P
''',
    'covariance_matrix': r'''import numpy as np


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
    if P.shape != Q.shape:
        raise ValueError(f"P and Q must have the same shape, got {P.shape} and {Q.shape}")
    if P.ndim != 2:
        raise ValueError(f"P and Q must be (k, d) arrays, got shape {P.shape}")
    weights = np.ones(P.shape[0]) if w is None else np.asarray(w, dtype=float)
    p_mean = centroid(P, weights)
    q_mean = centroid(Q, weights)
    return ((P - p_mean) * weights[:, None]).T @ (Q - q_mean)
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
    if S.ndim != 2 or S.shape[0] != S.shape[1]:
        raise ValueError(f"S must be a square (d, d) matrix, got shape {S.shape}")
    if not np.all(np.isfinite(S)):
        raise ValueError("S contains NaN or infinite entries")
    U_, s_, Vt_ = np.linalg.svd(S)
    return Vt_.T @ U_.T
''',
    'orthogonal_align': r'''import numpy as np


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
    P = np.asarray(P, dtype=float)
    Q = np.asarray(Q, dtype=float)
    if P.shape != Q.shape:
        raise ValueError(f"P and Q must have the same shape, got {P.shape} and {Q.shape}")
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    t = centroid(Q, w) - R @ centroid(P, w)
    return R, t
''',
}
LOSES = set()
