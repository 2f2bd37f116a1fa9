"""Stage 01, shape matching: the best orthogonal map between two point sets."""

import numpy as np

from starter.validation import as_float_array, as_points, as_weights


def centroid(P, w=None):
    """Weighted mean of a point set.

    Parameters
    ----------
    P : (k, d) array_like of float
        Points, ``d`` in {2, 3}.
    w : (k,) array_like of float, optional
        Non-negative weights with a positive sum; default all ones.

    Returns
    -------
    c : (d,) numpy.ndarray
        ``Σ w_i p_i / Σ w_i``.
    """
    P = as_points(P, "P")
    w = as_weights(w, len(P))
    # normalizing first keeps tiny or huge weights from under- or overflowing
    return (w / w.sum()) @ P


def covariance_matrix(P, Q, w=None):
    """Weighted cross-covariance of two corresponding point sets.

    Parameters
    ----------
    P : (k, d) array_like of float
        Source points, ``d`` in {2, 3}.
    Q : (k, d) array_like of float
        Target points, ``Q[i]`` corresponds to ``P[i]``.
    w : (k,) array_like of float, optional
        Non-negative weights with a positive sum; default all ones.

    Returns
    -------
    S : (d, d) numpy.ndarray
        ``Σ w_i (p_i - p̄)(q_i - q̄)ᵀ`` with the weighted centroids ``p̄``, ``q̄``.
    """
    P = as_points(P, "P")
    Q = as_points(Q, "Q")
    if Q.shape != P.shape:
        raise ValueError(
            f"Q must have the same shape as P (one corresponding point per row), "
            f"got P {P.shape} and Q {Q.shape}"
        )
    w = as_weights(w, len(P))
    P_c = P - centroid(P, w)
    Q_c = Q - centroid(Q, w)
    return P_c.T @ (w[:, None] * Q_c)


def optimal_orthogonal(S):
    """Orthogonal matrix maximizing ``tr(R S)``.

    Parameters
    ----------
    S : (d, d) array_like of float
        ``d`` in {2, 3}, typically a covariance matrix.

    Returns
    -------
    R : (d, d) numpy.ndarray
        ``R = Ũ Uᵀ`` for the SVD ``S = U Σ Ũᵀ``; orthogonal, possibly a
        reflection. Any maximizer is correct when ``S`` is rank-deficient.
    """
    S = as_float_array(S, "S", ndim=2)
    if S.shape not in ((2, 2), (3, 3)):
        raise ValueError(f"S must be a (d, d) matrix with d in (2, 3), got shape {S.shape}")
    U, _, Vt = np.linalg.svd(S)
    return Vt.T @ U.T


def orthogonal_align(P, Q, w=None):
    """Orthogonal map and translation best aligning ``P`` to ``Q``.

    Parameters
    ----------
    P : (k, d) array_like of float
        Source points, ``d`` in {2, 3}.
    Q : (k, d) array_like of float
        Target points, ``Q[i]`` corresponds to ``P[i]``.
    w : (k,) array_like of float, optional
        Non-negative weights with a positive sum; default all ones.

    Returns
    -------
    R : (d, d) numpy.ndarray
        Orthogonal (possibly a reflection).
    t : (d,) numpy.ndarray
        Translation; ``(R, t)`` minimizes ``Σ w_i ‖R p_i + t - q_i‖²``.
    """
    S = covariance_matrix(P, Q, w)
    R = optimal_orthogonal(S)
    t = centroid(Q, w) - R @ centroid(P, w)
    return R, t
