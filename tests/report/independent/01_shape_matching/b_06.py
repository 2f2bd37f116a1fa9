NOTEBOOK = "01_shape_matching"
DESCRIPTION = "least-squares minded student: centroid and translation from the normal equations (lstsq), SVD only where required"
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
    k = P.shape[0]
    w = np.ones(k) if w is None else np.asarray(w, dtype=np.float64)
    # p_bar minimizes sum_i w_i |p_i - c|^2: a weighted least-squares problem
    sw = np.sqrt(w)
    A = sw[:, None]                      # (k, 1) design matrix of ones, weighted
    b = sw[:, None] * P                  # (k, d)
    c, *_ = np.linalg.lstsq(A, b, rcond=None)
    return c[0]
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
    w = np.ones(P.shape[0]) if w is None else np.asarray(w, dtype=np.float64)
    X = P - centroid(P, w)
    Y = Q - centroid(Q, w)
    # S = X^T W Y
    return X.T @ (Y * w[:, None])
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
    # here no least-squares shortcut: the orthogonality constraint needs the SVD
    U_s, sv, Vt_s = np.linalg.svd(np.asarray(S, dtype=np.float64))
    return Vt_s.T.dot(U_s.T)
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    # for fixed R, t solves the normal equations (sum w) t = sum w (q_i - R p_i)
    w_ = np.ones(len(P)) if w is None else np.asarray(w, dtype=np.float64)
    residual = Q - P @ R.T
    t = np.linalg.solve(np.array([[w_.sum()]]), (w_ @ residual)[None, :])[0]
    return R, t
''',
}
LOSES = set()
