NOTEBOOK = '01_shape_matching'
DESCRIPTION = '03 engineer who likes scipy: np.average, scipy.linalg.svd, diag weighting via scipy.sparse.diags'
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
    P = np.asarray(P, dtype=np.float64)
    return np.average(P, axis=0, weights=w)
''',
    'covariance_matrix': r'''import numpy as np
import scipy.sparse as sp


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
    P = np.asarray(P, dtype=np.float64)
    Q = np.asarray(Q, dtype=np.float64)
    k = P.shape[0]
    if w is None:
        w = np.ones(k)
    w = np.asarray(w, dtype=np.float64)
    Pc = P - np.average(P, axis=0, weights=w)
    Qc = Q - np.average(Q, axis=0, weights=w)
    W = sp.diags(w)
    return np.asarray(Pc.T @ (W @ Qc))
''',
    'optimal_orthogonal': r'''import numpy as np
import scipy.linalg


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
    U, sv, Vh = scipy.linalg.svd(np.asarray(S, dtype=np.float64), lapack_driver="gesvd")
    return Vh.T.dot(U.T)
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
    S = covariance_matrix(P, Q, w)
    R = optimal_orthogonal(S)
    t = centroid(Q, w) - R.dot(centroid(P, w))
    return R, np.asarray(t)
''',
}
LOSES = set()
