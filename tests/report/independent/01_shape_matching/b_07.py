NOTEBOOK = "01_shape_matching"
DESCRIPTION = "geometry student: special-cases the unweighted mean, sums of outer products via np.einsum over points, transposes the SVD by hand"
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
    pts = np.asarray(P, dtype=float)
    if w is None:
        return pts.mean(axis=0)
    weights = np.asarray(w, dtype=float)
    return weights @ pts / weights.sum()
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
    pts_p = np.asarray(P, dtype=float)
    pts_q = np.asarray(Q, dtype=float)
    weights = np.ones(len(pts_p)) if w is None else np.asarray(w, dtype=float)
    cp = centroid(pts_p, weights)
    cq = centroid(pts_q, weights)
    # sum of weighted outer products (p_i - cp)(q_i - cq)^T
    outer = (pts_p - cp)[:, :, None] * (pts_q - cq)[:, None, :]
    return np.tensordot(weights, outer, axes=1)
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
    left, sigma, right_T = np.linalg.svd(np.asarray(S, dtype=float))
    right = right_T.T
    left_T = left.T
    return np.matmul(right, left_T)
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
    cov = covariance_matrix(P, Q, w)
    rot = optimal_orthogonal(cov)
    shift = centroid(Q, w) - rot.dot(centroid(P, w))
    return rot, shift
''',
}
LOSES = set()
