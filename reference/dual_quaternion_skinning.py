"""Dual-quaternion skinning (Kavan, Collins, Žára, O'Sullivan 2008): blend rigid motions, not matrices.

A rigid transform ``x -> R x + t`` of 3-space is the unit dual quaternion
``q̂ = q_0 + ε q_e`` with ``q_0`` the rotation's unit quaternion and
``q_e = ½ (0, t) q_0``. Quaternions are stored ``(w, x, y, z)``; a dual
quaternion is a ``(2, 4)`` array ``[q_0, q_e]``.
"""

import numpy as np

from starter.validation import as_float_array, as_points


def dual_quaternions(T):
    """Unit dual quaternions of rigid transforms.

    Parameters
    ----------
    T : (m, 3, 4) array_like of float
        Rigid transforms ``[R_j | t_j]``, ``R_j`` a rotation (orthonormal to 1e-6, ``det R_j = +1``).

    Returns
    -------
    Q : (m, 2, 4) numpy.ndarray
        ``Q[j, 0]`` the unit quaternion ``(w, x, y, z)`` of ``R_j`` (with ``w >= 0``; ``-Q[j]``
        is the same transform), ``Q[j, 1] = ½ (0, t_j) Q[j, 0]`` (quaternion product).
    """
    T = as_float_array(T, "T", ndim=3)
    if T.shape[1:] != (3, 4):
        raise ValueError(f"T must have shape (m, 3, 4), one rigid transform [R | t] per handle, got {T.shape}")
    R, t = T[:, :, :3], T[:, :, 3]
    off = np.abs(np.einsum("jki,jkl->jil", R, R) - np.eye(3)).max(axis=(1, 2), initial=0.0)
    if np.any(off > 1e-6) or np.any(np.linalg.det(R) <= 0):
        j = int(np.argmax((off > 1e-6) | (np.linalg.det(R) <= 0)))
        raise ValueError(f"T[{j}] is not rigid: its 3x3 part must be a rotation (RᵀR = I, det R = +1)")
    # Shepperd's method: 4w² - 1 = tr R, 4x² - 1 = 2 R_00 - tr R, ...; solve for the largest first,
    # so that no division is by a small number.
    tr = np.einsum("jii->j", R)
    big = np.argmax(np.stack([tr, 2 * R[:, 0, 0] - tr, 2 * R[:, 1, 1] - tr, 2 * R[:, 2, 2] - tr], axis=1), axis=1)
    q = np.empty((len(R), 4))
    for k in range(4):
        sel = big == k
        r = R[sel]
        if k == 0:
            s = 2.0 * np.sqrt(1.0 + tr[sel])
            q[sel] = np.c_[s / 4, (r[:, 2, 1] - r[:, 1, 2]) / s, (r[:, 0, 2] - r[:, 2, 0]) / s, (r[:, 1, 0] - r[:, 0, 1]) / s]
        else:
            i, a, b = k - 1, k % 3, (k + 1) % 3
            s = 2.0 * np.sqrt(np.maximum(1.0 + 2.0 * r[:, i, i] - tr[sel], 0.0))
            row = np.empty((len(r), 4))
            row[:, 0] = (r[:, b, a] - r[:, a, b]) / s
            row[:, 1 + i] = s / 4
            row[:, 1 + a] = (r[:, a, i] + r[:, i, a]) / s
            row[:, 1 + b] = (r[:, b, i] + r[:, i, b]) / s
            q[sel] = row
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 0] < 0] *= -1.0
    w, v = q[:, 0], q[:, 1:]
    # ½ (0, t) q = ½ (-t·v, w t + t × v)
    qe = 0.5 * np.c_[-np.einsum("ji,ji->j", t, v), w[:, None] * t + np.cross(t, v)]
    return np.stack([q, qe], axis=1)


def dual_quaternion_transforms(Q):
    """Rigid transforms of dual quaternions, normalized first.

    Parameters
    ----------
    Q : (k, 2, 4) array_like of float
        Dual quaternions ``[q_0, q_e]`` (``(w, x, y, z)`` each), ``q_0 != 0``; not necessarily unit,
        e.g. a weighted sum of unit dual quaternions.

    Returns
    -------
    T : (k, 3, 4) numpy.ndarray
        With ``c_0 = q_0 / ‖q_0‖``, ``c_e = q_e / ‖q_0‖``: ``R`` the rotation of ``c_0`` and
        ``t = 2 vec(c_e c̄_0)`` (``c̄_0`` the conjugate), ``T = [R | t]``. ``Q`` and ``-Q`` give the same ``T``.
    """
    Q = as_float_array(Q, "Q", ndim=3)
    if Q.shape[1:] != (2, 4):
        raise ValueError(f"Q must have shape (k, 2, 4), one dual quaternion [q_0, q_e] per row, got {Q.shape}")
    norm = np.linalg.norm(Q[:, 0], axis=1)
    if np.any(norm < 1e-12):
        raise ValueError(f"Q[{int(np.argmin(norm))}, 0] (the real part) is zero: it has no rotation")
    c0, ce = Q[:, 0] / norm[:, None], Q[:, 1] / norm[:, None]
    w, x, y, z = c0.T
    R = np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=1),
        ],
        axis=1,
    )
    # vec(c_e c̄_0) = w c_e,vec - w_e c_0,vec - c_e,vec × c_0,vec
    t = 2.0 * (w[:, None] * ce[:, 1:] - ce[:, :1] * c0[:, 1:] - np.cross(ce[:, 1:], c0[:, 1:]))
    return np.concatenate([R, t[:, :, None]], axis=2)


def dqs(V, W, T):
    """Deform a mesh by dual-quaternion skinning, as libigl's C++ ``igl::dqs`` (not in its python bindings).

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions.
    W : (n, m) array_like of float
        Skinning weights, one column per handle; no row may blend its rotations to zero.
    T : (m, 3, 4) array_like of float
        One rigid transform ``[R_j | t_j]`` per handle.

    Returns
    -------
    U : (n, 3) numpy.ndarray
        ``u_i = T̂_i [v_i; 1]`` with ``T̂_i = dual_quaternion_transforms(Σ_j W[i, j] s_j q̂_j)``,
        ``q̂_j = dual_quaternions(T)[j]`` and ``s_j = ±1`` such that ``s_j q_{j,0} · q_{0,0} >= 0``
        (every handle on the side of handle 0's quaternion, the pivot, as ``igl.dqs`` does).
    """
    V = as_points(V, "V", dims=(3,))
    W = as_float_array(W, "W", ndim=2)
    n = len(V)
    if W.shape[0] != n or W.shape[1] == 0:
        raise ValueError(
            f"W must have shape ({n}, m), one row per vertex of V and m >= 1 handle columns, got {W.shape}"
        )
    m = W.shape[1]
    T = as_float_array(T, "T", ndim=3)
    if T.shape != (m, 3, 4):
        raise ValueError(f"T must have shape ({m}, 3, 4), one rigid transform per column of W, got {T.shape}")
    Q = dual_quaternions(T)
    Q[Q[:, 0] @ Q[0, 0] < 0] *= -1.0
    B = (W @ Q.reshape(m, 8)).reshape(n, 2, 4)
    norm = np.linalg.norm(B[:, 0], axis=1)
    if np.any(norm < 1e-12):
        raise ValueError(f"W[{int(np.argmin(norm))}] blends the handles' rotations to zero: that vertex has no rotation")
    c0, ce = B[:, 0] / norm[:, None], B[:, 1] / norm[:, None]
    a0, d0, ae, de = c0[:, :1], c0[:, 1:], ce[:, :1], ce[:, 1:]
    # R v = v + 2 d0 × (d0 × v + a0 v) for the unit quaternion (a0, d0); t = 2 vec(c_e c̄_0)
    return V + 2.0 * np.cross(d0, np.cross(d0, V) + a0 * V) + 2.0 * (a0 * de - ae * d0 + np.cross(d0, de))
