"""Stage 05, linear blend skinning: ``u_i = Σ_j W[i, j] T_j [v_i; 1]``."""

import numpy as np

from starter.validation import as_float_array, as_vertices


def lbs_matrix(V, W):
    """Linear blend skinning matrix, equal to ``igl.lbs_matrix(V, W)``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    W : (n, m) array_like of float
        Skinning weights, one column per handle.

    Returns
    -------
    M : (n, m(d+1)) numpy.ndarray
        ``M[i, j(d+1)+c] = W[i, j]·[v_i; 1][c]``, so that ``U = M @ Tstack``
        with ``Tstack = vstack(T_jᵀ)`` of shape ``(m(d+1), d)``.
    """
    V = as_vertices(V)
    W = as_float_array(W, "W", ndim=2)
    n, m = W.shape
    if n != len(V) or m == 0:
        raise ValueError(
            f"W must have shape ({len(V)}, m), one row per vertex of V and m >= 1 handle columns, "
            f"got {W.shape}"
        )
    V_h = np.hstack([V, np.ones((n, 1))])
    return (W[:, :, None] * V_h[:, None, :]).reshape(n, -1)


def lbs(V, W, T):
    """Deform a mesh by linear blend skinning.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    W : (n, m) array_like of float
        Skinning weights, one column per handle.
    T : (m, d, d+1) array_like of float
        One affine transform ``[A_j | t_j]`` per handle.

    Returns
    -------
    U : (n, d) numpy.ndarray
        ``u_i = Σ_j W[i, j] (A_j v_i + t_j)``.
    """
    V = as_vertices(V)
    W = as_float_array(W, "W", ndim=2)
    n, d = V.shape
    if W.shape[0] != n or W.shape[1] == 0:
        raise ValueError(
            f"W must have shape ({n}, m), one row per vertex of V and m >= 1 handle columns, "
            f"got {W.shape}"
        )
    m = W.shape[1]
    T = as_float_array(T, "T", ndim=3)
    if T.shape != (m, d, d + 1):
        raise ValueError(
            f"T must have shape ({m}, {d}, {d + 1}), one affine transform per column of W, got {T.shape}"
        )
    return np.einsum("ij,jab,ib->ia", W, T[:, :, :d], V) + W @ T[:, :, d]
