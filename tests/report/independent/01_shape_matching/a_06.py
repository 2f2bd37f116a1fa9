NOTEBOOK = '01_shape_matching'
DESCRIPTION = '06 competitive programmer: terse one-liners, short names'
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
    if w is None:return np.mean(P,0)
    return np.dot(w,P)/np.sum(w)
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
    w=np.ones(len(P)) if w is None else np.asarray(w,float)
    a,b=np.asarray(P,float),np.asarray(Q,float)
    return ((a-centroid(a,w)).T*w)@(b-centroid(b,w))
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
    u,_,v=np.linalg.svd(S);return (u@v).T
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
    R=optimal_orthogonal(covariance_matrix(P,Q,w));return R,centroid(Q,w)-R@centroid(P,w)
''',
}
LOSES = set()
