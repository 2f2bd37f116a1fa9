NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 01: functional style, list comprehensions and zip over the point pairs.'
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
    pts = np.asarray(P, dtype=float)
    ws = [1.0] * len(pts) if w is None else [float(x) for x in w]
    total = sum(ws)
    return np.array([sum(wi * p[j] for wi, p in zip(ws, pts)) / total for j in range(pts.shape[1])])
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
    ps, qs = np.asarray(P, dtype=float), np.asarray(Q, dtype=float)
    ws = [1.0] * len(ps) if w is None else [float(x) for x in w]
    pc, qc = centroid(ps, ws), centroid(qs, ws)
    terms = [wi * np.outer(p - pc, q - qc) for wi, p, q in zip(ws, ps, qs)]
    return np.sum(np.array(terms), axis=0)
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
    left, _, right_t = np.linalg.svd(np.asarray(S, dtype=float))
    # R[i, j] = sum_k V~[i, k] U~[j, k]
    return np.array([[np.dot(vrow, urow) for urow in left] for vrow in right_t.T])
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    p_bar, q_bar = (centroid(X, w) for X in (P, Q))
    return R, q_bar - R @ p_bar
''',
}
LOSES = set()
