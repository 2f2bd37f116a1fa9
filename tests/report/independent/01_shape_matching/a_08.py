NOTEBOOK = '01_shape_matching'
DESCRIPTION = '08 collects intermediate results in dicts (a prepare helper returning a dict) and reuses them'
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
    P = np.asarray(P, dtype=float)
    if w is None:
        return P.mean(axis=0)
    w = np.asarray(w, dtype=float)
    return (w[:, None] * P).sum(axis=0) / w.sum()
''',
    'covariance_matrix': r'''import numpy as np


def _prepare(P, Q, w):
    data = {}
    data["P"] = np.asarray(P, dtype=float)
    data["Q"] = np.asarray(Q, dtype=float)
    data["w"] = np.ones(len(data["P"])) if w is None else np.asarray(w, dtype=float)
    data["p_bar"] = centroid(data["P"], data["w"])
    data["q_bar"] = centroid(data["Q"], data["w"])
    data["P_c"] = data["P"] - data["p_bar"]
    data["Q_c"] = data["Q"] - data["q_bar"]
    return data


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
    data = _prepare(P, Q, w)
    return np.dot(data["P_c"].T, data["w"][:, None] * data["Q_c"])
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
    svd = dict(zip(("U", "sigma", "Vt"), np.linalg.svd(np.asarray(S, dtype=float))))
    return np.dot(svd["Vt"].T, svd["U"].T)
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
    data = _prepare(P, Q, w)
    S = np.dot(data["P_c"].T, data["w"][:, None] * data["Q_c"])
    R = optimal_orthogonal(S)
    return R, data["q_bar"] - np.dot(R, data["p_bar"])
''',
}
LOSES = set()
