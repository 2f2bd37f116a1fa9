NOTEBOOK = "01_shape_matching"
DESCRIPTION = "array-programming data-science student: normalized weights, w @ P, einsum for S, full_matrices=False SVD"
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
    P = np.asarray(P, float)
    w = np.ones(P.shape[0]) if w is None else np.asarray(w, float)
    return (w / w.sum()) @ P
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
    P, Q = np.asarray(P, float), np.asarray(Q, float)
    w = np.ones(len(P)) if w is None else np.asarray(w, float)
    dP = P - centroid(P, w)
    dQ = Q - centroid(Q, w)
    return np.einsum("k,ki,kj->ij", w, dP, dQ)
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
    u, s, vh = np.linalg.svd(np.asarray(S, float), full_matrices=False)
    return (u @ vh).T
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
    return R, centroid(Q, w) - centroid(P, w) @ R.T
''',
}
LOSES = set()
