NOTEBOOK = "01_shape_matching"
DESCRIPTION = 'Student 07: treats 2D and 3D separately with explicit if/else branches on the dimension.'
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
    n = P.shape[0]
    if w is None:
        w = np.ones(n)
    else:
        w = np.asarray(w, dtype=float)
    total = w.sum()
    if P.shape[1] == 2:
        cx = np.sum(w * P[:, 0]) / total
        cy = np.sum(w * P[:, 1]) / total
        return np.array([cx, cy])
    else:
        cx = np.sum(w * P[:, 0]) / total
        cy = np.sum(w * P[:, 1]) / total
        cz = np.sum(w * P[:, 2]) / total
        return np.array([cx, cy, cz])
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
    n, dim = P.shape
    if w is None:
        w = np.ones(n)
    else:
        w = np.asarray(w, dtype=float)
    A = P - centroid(P, w)
    B = Q - centroid(Q, w)
    if dim == 2:
        S = np.zeros((2, 2))
        for a in range(2):
            for b in range(2):
                S[a, b] = np.sum(w * A[:, a] * B[:, b])
    else:
        S = np.zeros((3, 3))
        for a in range(3):
            for b in range(3):
                S[a, b] = np.sum(w * A[:, a] * B[:, b])
    return S
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
    S = np.asarray(S, dtype=float)
    if S.shape[0] == 2:
        Usvd, sing, VsvdT = np.linalg.svd(S)
        R = VsvdT.T @ Usvd.T
    else:
        Usvd, sing, VsvdT = np.linalg.svd(S)
        R = VsvdT.T @ Usvd.T
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
    S = covariance_matrix(P, Q, w)
    R = optimal_orthogonal(S)
    cp = centroid(P, w)
    cq = centroid(Q, w)
    if len(cp) == 2:
        t = np.array([cq[0] - (R[0, 0] * cp[0] + R[0, 1] * cp[1]),
                      cq[1] - (R[1, 0] * cp[0] + R[1, 1] * cp[1])])
    else:
        t = cq - R @ cp
    return R, t
''',
}
LOSES = set()
