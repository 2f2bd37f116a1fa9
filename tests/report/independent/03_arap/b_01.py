NOTEBOOK = "03_arap"
DESCRIPTION = "graphics enthusiast using the ARAP paper's notation (e_ij, w_ij, S_i, R_i); einsum everywhere, splu for the global step"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


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
    # S_i = U_i Sigma_i V_i^T, R_i = V_i D U_i^T (Sorkine & Alexa 2007, eq. 6)
    U_i, _, V_iT = np.linalg.svd(S)
    V_i = np.swapaxes(V_iT, -1, -2)
    U_iT = np.swapaxes(U_i, -1, -2)
    det = np.linalg.det(V_i @ U_iT)
    D = np.ones(S.shape[:-1])
    D[..., -1] = np.sign(det)
    # V_i diag(D) U_i^T: scale the columns of V_i
    return (V_i * D[..., None, :]) @ U_iT
''',
    "cotangent_weights": '''import numpy as np


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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    C = np.zeros(F.shape, dtype=float)
    for k in range(3):
        i = F[:, k]
        j = F[:, (k + 1) % 3]
        l = F[:, (k + 2) % 3]
        e_ij = V[j] - V[i]
        e_il = V[l] - V[i]
        dot = np.sum(e_ij * e_il, axis=1)
        if V.shape[1] == 2:
            cross = np.abs(e_ij[:, 0] * e_il[:, 1] - e_ij[:, 1] * e_il[:, 0])
        else:
            cross = np.linalg.norm(np.cross(e_ij, e_il), axis=1)
        C[:, k] = 0.5 * dot / cross
    return C
''',
    "cotangent_laplacian": '''import numpy as np
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
    F = np.asarray(F)
    n = len(V)
    w = cotangent_weights(V, F)
    # w_ij for the edge opposite corner k
    i = np.concatenate([F[:, (k + 1) % 3] for k in range(3)])
    j = np.concatenate([F[:, (k + 2) % 3] for k in range(3)])
    w_ij = np.concatenate([w[:, k] for k in range(3)])
    W = sp.coo_matrix((np.concatenate([w_ij, w_ij]), (np.concatenate([i, j]), np.concatenate([j, i]))), shape=(n, n)).tocsr()
    L = W - sp.diags(np.asarray(W.sum(axis=1)).ravel())
    return L.tocsr()
''',
    "arap_covariances": '''import numpy as np
import scipy.sparse as sp


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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F)
    C = np.asarray(C, dtype=float)
    n, d = V.shape
    # e_ij (rest) and e'_ij (deformed) for the three edges of every triangle: (f, 3, d)
    nxt = F[:, [1, 2, 0]]
    prv = F[:, [2, 0, 1]]
    e = V[nxt] - V[prv]
    e_def = U[nxt] - U[prv]
    # per triangle: sum_k w_k e_k e'_k^T
    S_T = np.einsum("tk,tka,tkb->tab", C, e, e_def)
    S = np.zeros((n, d, d))
    for k in range(3):
        np.add.at(S, F[:, k], S_T)
    return S
''',
    "arap_rotations": '''def arap_rotations(V, U, F, C):
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
    S_i = arap_covariances(V, U, F, C)
    return optimal_rotation(S_i)
''',
    "arap_energy": '''import numpy as np


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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F)
    C = np.asarray(C, dtype=float)
    R = np.asarray(R, dtype=float)
    nxt = F[:, [1, 2, 0]]
    prv = F[:, [2, 0, 1]]
    e = V[nxt] - V[prv]              # (f, 3 edges, d)
    e_def = U[nxt] - U[prv]
    R_T = R[F]                       # (f, 3 corners, d, d)
    # r[t, i, k] = e'_k - R_i e_k
    r = e_def[:, None, :, :] - np.einsum("tiab,tkb->tika", R_T, e)
    return float(np.einsum("tk,tika,tika->", C, r, r))
''',
}
LOSES = set()
