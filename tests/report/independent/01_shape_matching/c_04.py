NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 04: exchange student, French comments and French variable names (poids, points, ecarts), np.average.'
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
    # moyenne ponderee des points (poids uniformes par defaut)
    points = np.asarray(P, dtype=float)
    poids = None if w is None else np.asarray(w, dtype=float)
    return np.average(points, axis=0, weights=poids)
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
    points_p = np.asarray(P, dtype=float)
    points_q = np.asarray(Q, dtype=float)
    if w is None:
        poids = np.ones(points_p.shape[0])
    else:
        poids = np.asarray(w, dtype=float)
    # on centre avec les barycentres ponderes
    ecarts_p = points_p - centroid(points_p, poids)
    ecarts_q = points_q - centroid(points_q, poids)
    # S = P~^T W Q~, sans construire la matrice diagonale W
    return ecarts_p.T @ (poids[:, None] * ecarts_q)
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
    # decomposition en valeurs singulieres : S = U diag(sigma) V^T
    U_gauche, valeurs_sing, Vt_droite = np.linalg.svd(np.asarray(S, dtype=float))
    # attention : numpy renvoie deja V^T
    rotation = Vt_droite.T @ U_gauche.T
    return rotation
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
    # la partie orthogonale vient de la matrice de covariance
    rotation = optimal_orthogonal(covariance_matrix(P, Q, w))
    # la translation envoie le barycentre de P sur celui de Q
    barycentre_p = centroid(P, w)
    barycentre_q = centroid(Q, w)
    translation = barycentre_q - rotation @ barycentre_p
    return rotation, translation
''',
}
LOSES = set()
