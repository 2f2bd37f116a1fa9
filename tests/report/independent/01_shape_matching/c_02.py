NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 02: array-building style (np.stack / np.newaxis broadcasting, einsum) with detailed comments on every step.'
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
    # convert to a float array so that integer input and lists work as well
    points = np.asarray(P, dtype=np.float64)
    # default weights: every point counts the same
    if w is None:
        weights = np.ones(points.shape[0], dtype=np.float64)
    else:
        weights = np.asarray(w, dtype=np.float64)
    # weight every row (broadcast the (k,) weights to (k, 1)), add the rows up,
    # and divide by the total weight (NOT by the number of points)
    weighted_sum = np.sum(weights[:, np.newaxis] * points, axis=0)
    return weighted_sum / np.sum(weights)
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
    # float arrays of shape (k, d)
    source = np.asarray(P, dtype=np.float64)
    target = np.asarray(Q, dtype=np.float64)
    # weights (k,), all ones if not given
    if w is None:
        weights = np.ones(source.shape[0], dtype=np.float64)
    else:
        weights = np.asarray(w, dtype=np.float64)
    # centre both point sets with their *weighted* centroids
    source_centred = source - centroid(source, weights)[np.newaxis, :]
    target_centred = target - centroid(target, weights)[np.newaxis, :]
    # S[a, b] = sum_i w_i * p~_i[a] * q~_i[b]  (p on the left, q on the right)
    return np.einsum("i,ia,ib->ab", weights, source_centred, target_centred)
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
    S_arr = np.asarray(S, dtype=np.float64)
    # numpy factorizes S = U_svd @ diag(s) @ Vh, i.e. Vh is already V~ transposed
    U_svd, s, Vh = np.linalg.svd(S_arr)
    # R = V~ U~^T = Vh^T U_svd^T = (U_svd Vh)^T
    return (U_svd @ Vh).T
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
    # 1) the orthogonal part from the weighted covariance matrix
    S = covariance_matrix(P, Q, w)
    R = optimal_orthogonal(S)
    # 2) both weighted centroids, stacked as rows: row 0 = p_bar, row 1 = q_bar
    centres = np.stack([centroid(P, w), centroid(Q, w)], axis=0)
    # 3) the translation maps R p_bar onto q_bar
    t = centres[1] - R @ centres[0]
    return R, t
''',
}
LOSES = set()
