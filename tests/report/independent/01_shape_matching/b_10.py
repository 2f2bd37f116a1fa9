NOTEBOOK = "01_shape_matching"
DESCRIPTION = "reuse-everything student: a tiny _weights helper re-derived in each cell, every function built on the previous ones"
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
    P = np.asarray(P, dtype=float)
    if w is None:
        w = np.ones(len(P))
    w = np.asarray(w, dtype=float)
    return np.einsum("i,ij->j", w, P) / w.sum()
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
    # numpy already has a weighted covariance: np.cov with aweights (bias=True divides by sum w)
    P = np.asarray(P, dtype=float)
    d = P.shape[1]
    weights = None if w is None else np.asarray(w, dtype=float)
    total = len(P) if w is None else weights.sum()
    full = np.cov(P, np.asarray(Q, dtype=float), rowvar=False, aweights=weights, bias=True)
    return full[:d, d:] * total
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
    u, _, vt = np.linalg.svd(S)
    return np.transpose(vt) @ np.transpose(u)
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
    return R, centroid(np.asarray(Q, dtype=float) - np.asarray(P, dtype=float) @ R.T, w)
''',
}
LOSES = set()
