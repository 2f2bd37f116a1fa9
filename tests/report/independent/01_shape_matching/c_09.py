NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 09: computes the ingredients first (total weight, centred points, diagonal weight matrix) then combines them with matrix products.'
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
    pts = np.array(P, dtype=np.float64)
    k = len(pts)
    weights = np.ones(k) if w is None else np.array(w, dtype=np.float64)
    total_weight = np.sum(weights)
    weighted_points = pts * weights.reshape(-1, 1)
    return weighted_points.sum(axis=0) / total_weight
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
    pts_p = np.array(P, dtype=np.float64)
    pts_q = np.array(Q, dtype=np.float64)
    k = len(pts_p)
    weights = np.ones(k) if w is None else np.array(w, dtype=np.float64)
    mean_p = centroid(pts_p, weights)
    mean_q = centroid(pts_q, weights)
    centred_p = pts_p - mean_p
    centred_q = pts_q - mean_q
    W = np.diag(weights)
    return centred_p.T @ W @ centred_q
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
    mat = np.array(S, dtype=np.float64)
    svd_u, singular_values, svd_vh = np.linalg.svd(mat)
    svd_v = svd_vh.T
    return svd_v @ svd_u.T
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
    mean_p = centroid(P, w)
    mean_q = centroid(Q, w)
    cov = covariance_matrix(P, Q, w)
    rot = optimal_orthogonal(cov)
    trans = mean_q - rot @ mean_p
    return rot, trans
''',
}
LOSES = set()
