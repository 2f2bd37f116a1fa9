NOTEBOOK = '03_arap'
DESCRIPTION = '10 careful validator: every function checks shapes, indices and values (ValueError), cos/sin cotangents, sparse scatter matrix for B'
SOLUTIONS = {
    'optimal_rotation': r'''import numpy as np


def optimal_rotation(S):
    """The rotation maximizing ``tr(R S)``, for one matrix or a stack of them.

    Parameters
    ----------
    S : (d, d) or (k, d, d) array_like of float
        Covariance matrix or matrices, ``S = Ũ Σ Ṽᵀ``.

    Returns
    -------
    R : numpy.ndarray, the shape of ``S``
        ``R = Ṽ diag(1, …, 1, det(Ṽ Ũᵀ)) Ũᵀ``: orthogonal with ``det R = +1``.
    """
    S = np.asarray(S, dtype=float)
    if S.ndim not in (2, 3) or S.shape[-1] != S.shape[-2]:
        raise ValueError(f"S must be (d, d) or (k, d, d), got shape {S.shape}")
    if not np.all(np.isfinite(S)):
        raise ValueError("S contains NaN or infinite entries")
    U_, s_, Vt_ = np.linalg.svd(S)
    V_ = np.swapaxes(Vt_, -1, -2)
    Ut_ = np.swapaxes(U_, -1, -2)
    det = np.linalg.det(V_ @ Ut_)
    d = S.shape[-1]
    D = np.broadcast_to(np.eye(d), S.shape).copy()
    D[..., d - 1, d - 1] = np.where(det < 0.0, -1.0, 1.0)
    return V_ @ D @ Ut_
''',
    'cotangent_weights': r'''import numpy as np


def _check_mesh(V, F):
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise ValueError(f"V must be (n, 2) or (n, 3), got shape {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError(f"F must be (f, 3), got shape {F.shape}")
    if not np.issubdtype(F.dtype, np.integer):
        raise ValueError("F must contain integer vertex indices")
    if F.size and (F.min() < 0 or F.max() >= len(V)):
        raise ValueError("F refers to vertices that do not exist")
    return V, F.astype(np.int64)


def cotangent_weights(V, F):
    """Half the cotangent of every triangle corner.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles, none of zero area.

    Returns
    -------
    C : (f, 3) numpy.ndarray
        ``C[t, k] = ½ cot`` of the angle at corner ``k`` of triangle ``t``: the weight of
        the opposite edge ``(F[t, (k+1)%3], F[t, (k+2)%3])``.
    """
    V, F = _check_mesh(V, F)
    C = np.zeros((len(F), 3))
    for k in range(3):
        a = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        b = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        la = np.linalg.norm(a, axis=1)
        lb = np.linalg.norm(b, axis=1)
        if V.shape[1] == 2:
            cr = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        else:
            cr = np.linalg.norm(np.cross(a, b), axis=1)
        if np.any(cr <= 1e-300):
            raise ValueError("F contains a triangle of zero area")
        cos_angle = np.sum(a * b, axis=1) / (la * lb)
        sin_angle = cr / (la * lb)
        C[:, k] = 0.5 * cos_angle / sin_angle
    return C
''',
    'cotangent_laplacian': r'''import numpy as np
import scipy.sparse as sp


def cotangent_laplacian(V, F):
    """The cotangent Laplacian (libigl's sign: negative semi-definite).

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        Symmetric; ``L[i, j]`` is the sum of the cotangent weights of edge ``(i, j)``,
        ``L[i, i] = -Σ_{j≠i} L[i, j]``.
    """
    V, F = _check_mesh(V, F)
    n = V.shape[0]
    C = cotangent_weights(V, F)
    i = F[:, [1, 2, 0]].reshape(-1)
    j = F[:, [2, 0, 1]].reshape(-1)
    c = C.reshape(-1)
    W = sp.coo_matrix((np.concatenate((c, c)), (np.concatenate((i, j)), np.concatenate((j, i)))), shape=(n, n))
    W.sum_duplicates()
    W = W.tocsc()
    degree = np.asarray(W.sum(axis=0)).reshape(-1)
    L = W - sp.diags(degree, format="csc")
    return L
''',
    'arap_covariances': r'''import numpy as np


def _check_deformation(V, U, F, C):
    V, F = _check_mesh(V, F)
    U = np.asarray(U, dtype=float)
    C = np.asarray(C, dtype=float)
    if U.shape != V.shape:
        raise ValueError(f"U must have the shape of V, {V.shape}, got {U.shape}")
    if C.shape != F.shape:
        raise ValueError(f"C must be (f, 3) = {F.shape}, got {C.shape}")
    return V, U, F, C


def arap_covariances(V, U, F, C):
    """The covariance matrix of every vertex's cell (the triangles around it).

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights, ``C[t, k]`` for the edge opposite corner ``k``.

    Returns
    -------
    S : (n, d, d) numpy.ndarray
        ``S_i = Σ_{t ∋ i} Σ_k C[t, k] e_tk e'_tkᵀ``, ``e_tk`` the rest edge opposite corner
        ``k`` and ``e'_tk`` the same edge in ``U``.
    """
    V, U, F, C = _check_deformation(V, U, F, C)
    n, d = V.shape
    S = np.zeros((n, d, d))
    tri = np.zeros((len(F), d, d))
    for k in range(3):
        p, q = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        e = V[q] - V[p]
        e_new = U[q] - U[p]
        tri += C[:, k, None, None] * np.matmul(e[:, :, None], e_new[:, None, :])
    for k in range(3):
        np.add.at(S, F[:, k], tri)
    return S
''',
    'arap_rotations': r'''def arap_rotations(V, U, F, C):
    """The local step: the best rotation of every vertex's cell.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.

    Returns
    -------
    R : (n, d, d) numpy.ndarray
        ``R_i = optimal_rotation(S_i)`` with ``S = arap_covariances(V, U, F, C)``.
    """
    S = arap_covariances(V, U, F, C)
    return optimal_rotation(S)
''',
    'arap_energy': r'''import numpy as np


def arap_energy(V, U, F, C, R):
    """The ARAP energy of positions ``U`` measured against one rotation per vertex.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.

    Returns
    -------
    E : float
        ``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²``.
    """
    V, U, F, C = _check_deformation(V, U, F, C)
    R = np.asarray(R, dtype=float)
    n, d = V.shape
    if R.shape != (n, d, d):
        raise ValueError(f"R must be (n, d, d) = {(n, d, d)}, got {R.shape}")
    f = len(F)
    tails, heads = F[:, [1, 2, 0]], F[:, [2, 0, 1]]
    e = V[heads] - V[tails]           # (f, 3, d)
    e_new = U[heads] - U[tails]
    # pair every corner rotation with every edge of the same triangle: (f, 3 corners, 3 edges)
    R_tc = R[F].reshape(f * 3, d, d)
    e_rep = np.repeat(e, 3, axis=0)                   # (3f, 3, d), same edges for each corner
    rotated = np.matmul(e_rep, np.swapaxes(R_tc, 1, 2)).reshape(f, 3, 3, d)
    residual = e_new[:, None, :, :] - rotated
    sq = np.sum(residual ** 2, axis=3)                # (f, corner, edge)
    return float(np.sum(sq * C[:, None, :]))
''',
}
LOSES = set()
