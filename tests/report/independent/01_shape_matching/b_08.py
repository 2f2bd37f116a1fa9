NOTEBOOK = "01_shape_matching"
DESCRIPTION = "cautious student: asserts on every shape, float64 conversions, checks the weight sum"
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
    P = np.asarray(P, dtype=np.float64)
    assert P.ndim == 2, "P must be (k, d)"
    k, d = P.shape
    if w is None:
        w = np.ones(k, dtype=np.float64)
    else:
        w = np.asarray(w, dtype=np.float64).reshape(-1)
    assert w.shape == (k,), "one weight per point"
    total = float(np.sum(w))
    assert total > 0.0, "weights must not all be zero"
    p_bar = np.dot(w, P) / total
    assert p_bar.shape == (d,)
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
    P = np.asarray(P, dtype=np.float64)
    Q = np.asarray(Q, dtype=np.float64)
    assert P.shape == Q.shape and P.ndim == 2, "P and Q must both be (k, d)"
    k, d = P.shape
    if w is None:
        w = np.ones(k, dtype=np.float64)
    w = np.asarray(w, dtype=np.float64).reshape(-1)
    assert w.shape == (k,)
    P_c = P - centroid(P, w)[np.newaxis, :]
    Q_c = Q - centroid(Q, w)[np.newaxis, :]
    S = np.matmul(P_c.T, w[:, np.newaxis] * Q_c)
    assert S.shape == (d, d)
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
    S = np.asarray(S, dtype=np.float64)
    assert S.ndim == 2 and S.shape[0] == S.shape[1], "S must be square"
    U_svd, sing, Vt_svd = np.linalg.svd(S)
    R = Vt_svd.T @ U_svd.T
    assert np.allclose(R.T @ R, np.eye(S.shape[0]))
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
    P = np.asarray(P, dtype=np.float64)
    Q = np.asarray(Q, dtype=np.float64)
    assert P.shape == Q.shape
    S = covariance_matrix(P, Q, w)
    R = optimal_orthogonal(S)
    t = centroid(Q, w) - R @ centroid(P, w)
    assert R.shape == (P.shape[1], P.shape[1]) and t.shape == (P.shape[1],)
    return R, t
''',
}
LOSES = set()
