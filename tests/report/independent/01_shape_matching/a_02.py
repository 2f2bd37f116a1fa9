NOTEBOOK = '01_shape_matching'
DESCRIPTION = '02 hurried student: explicit python loops over points and coordinates'
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
    if w is None:
        w = [1.0] * len(P)
    d = len(P[0])
    total = np.zeros(d)
    wsum = 0.0
    for i in range(len(P)):
        for c in range(d):
            total[c] += w[i] * P[i][c]
        wsum += w[i]
    return total / wsum
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
    if w is None:
        w = [1.0] * len(P)
    pc = centroid(P, w)
    qc = centroid(Q, w)
    d = len(pc)
    S = np.zeros((d, d))
    for i in range(len(P)):
        a = np.array(P[i], dtype=float) - pc
        b = np.array(Q[i], dtype=float) - qc
        for r in range(d):
            for c in range(d):
                S[r, c] += w[i] * a[r] * b[c]
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
    u, s, vt = np.linalg.svd(S)
    R = np.transpose(vt) @ np.transpose(u)
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
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    pc = centroid(P, w)
    qc = centroid(Q, w)
    t = qc - R.dot(pc)
    return R, t
''',
}
LOSES = set()
