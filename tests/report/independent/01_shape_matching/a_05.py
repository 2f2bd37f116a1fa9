NOTEBOOK = '01_shape_matching'
DESCRIPTION = '05 beginner following the slides step by step, many intermediate variables and comments'
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
    # step 1: make sure we have a numpy array
    points = np.array(P, dtype=float)
    number_of_points = points.shape[0]
    # step 2: if there are no weights, every point counts the same
    if w is None:
        weights = np.ones(number_of_points)
    else:
        weights = np.array(w, dtype=float)
    # step 3: weighted sum of the points (numerator of the formula)
    weighted_points = points * weights.reshape(-1, 1)
    numerator = weighted_points.sum(axis=0)
    # step 4: divide by the sum of the weights (denominator)
    denominator = weights.sum()
    p_bar = numerator / denominator
    return p_bar
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
    # step 1: arrays
    points_p = np.array(P, dtype=float)
    points_q = np.array(Q, dtype=float)
    number_of_points = points_p.shape[0]
    # step 2: weights (all ones if not given)
    if w is None:
        weights = np.ones(number_of_points)
    else:
        weights = np.array(w, dtype=float)
    # step 3: the weighted centroids from the first function
    p_bar = centroid(points_p, weights)
    q_bar = centroid(points_q, weights)
    # step 4: centre both point sets
    p_tilde = points_p - p_bar
    q_tilde = points_q - q_bar
    # step 5: S = P_tilde^T W Q_tilde, with W applied by broadcasting
    weighted_p_tilde = p_tilde * weights[:, None]
    S = weighted_p_tilde.T @ q_tilde
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
    # step 1: singular value decomposition, S = U_tilde Sigma V_tilde^T
    matrix_s = np.array(S, dtype=float)
    U_tilde, sigma, V_tilde_transposed = np.linalg.svd(matrix_s)
    # step 2: the third output is already V_tilde^T, so transpose it back
    V_tilde = V_tilde_transposed.T
    # step 3: R = V_tilde U_tilde^T (no sign correction in this notebook)
    U_tilde_transposed = U_tilde.T
    R = V_tilde @ U_tilde_transposed
    return R
''',
    'orthogonal_align': r'''def orthogonal_align(P, Q, w=None):
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
    # step 1: covariance of the two point sets
    S = covariance_matrix(P, Q, w)
    # step 2: best orthogonal matrix for this covariance
    R = optimal_orthogonal(S)
    # step 3: the centroids
    p_bar = centroid(P, w)
    q_bar = centroid(Q, w)
    # step 4: translation t = q_bar - R p_bar
    rotated_p_bar = R @ p_bar
    t = q_bar - rotated_p_bar
    return R, t
''',
}
LOSES = set()
