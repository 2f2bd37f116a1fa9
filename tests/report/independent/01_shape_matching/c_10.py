NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 10: generator expressions summed term by term (sum of weighted points, sum of outer products).'
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
    P = np.asarray(P, dtype=float)
    weights = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    num = sum((wi * pi for wi, pi in zip(weights, P)), np.zeros(P.shape[1]))
    return num / weights.sum()
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
    P = np.asarray(P, dtype=float)
    Q = np.asarray(Q, dtype=float)
    weights = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    p_bar, q_bar = centroid(P, weights), centroid(Q, weights)
    d = P.shape[1]
    return sum((wi * np.outer(pi - p_bar, qi - q_bar) for wi, pi, qi in zip(weights, P, Q)), np.zeros((d, d)))
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
    Ut, sigma, Vth = np.linalg.svd(np.asarray(S, dtype=float))
    R = np.einsum("ik,jk->ij", Vth.T, Ut)
    return R
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    p_bar, q_bar = centroid(P, w), centroid(Q, w)
    t = q_bar - np.einsum("ij,j->i", R, p_bar)
    return R, t
''',
}
LOSES = set()
