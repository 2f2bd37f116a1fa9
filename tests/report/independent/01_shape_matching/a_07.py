NOTEBOOK = '01_shape_matching'
DESCRIPTION = '07 physics student: displacement vectors from the centre of mass, S as a sum of np.outer products'
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
    pts = np.asarray(P, dtype=float)
    mass = np.ones(len(pts)) if w is None else np.asarray(w, dtype=float)
    # centre of mass: sum of m_i r_i over total mass M
    M = np.sum(mass)
    return np.sum(mass[:, None] * pts, axis=0) / M
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
    pts_p = np.asarray(P, dtype=float)
    pts_q = np.asarray(Q, dtype=float)
    mass = np.ones(len(pts_p)) if w is None else np.asarray(w, dtype=float)
    # position vectors relative to the centre of mass of each configuration
    r = pts_p - centroid(pts_p, mass)
    r_prime = pts_q - centroid(pts_q, mass)
    dim = pts_p.shape[1]
    S = np.zeros((dim, dim))
    for m, x, y in zip(mass, r, r_prime):
        S += m * np.outer(x, y)
    return S
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
    left, sv, right_h = np.linalg.svd(np.asarray(S, dtype=float))
    # S = left diag(sv) right_h, rotation R = right_h^T left^T
    return np.matmul(right_h.T, left.T)
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    com_p = centroid(P, w)
    com_q = centroid(Q, w)
    t = com_q - np.matmul(R, com_p)
    return R, t
''',
}
LOSES = set()
