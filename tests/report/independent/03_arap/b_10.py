NOTEBOOK = "03_arap"
DESCRIPTION = "reuse-everything student: energy from three arap_covariances calls (trace identity), Laplacian from weights, solve/editing only call earlier functions; rank-one reflection fix"
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
    u, _, vt = np.linalg.svd(S)
    R = np.swapaxes(vt, -1, -2) @ np.swapaxes(u, -1, -2)
    # a reflection: subtract twice the last singular pair, R - 2 v_d u_d^T
    neg = (np.linalg.det(R) < 0).astype(float)
    v_last = vt[..., -1, :]
    u_last = u[..., :, -1]
    fix = v_last[..., :, None] * u_last[..., None, :]
    return R - 2.0 * neg[..., None, None] * fix
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
    corners = V[F]
    to_next = corners[:, [1, 2, 0]] - corners
    to_prev = corners[:, [2, 0, 1]] - corners
    dot = np.einsum("tkd,tkd->tk", to_next, to_prev)
    if V.shape[1] == 2:
        cross = to_next[..., 0] * to_prev[..., 1] - to_next[..., 1] * to_prev[..., 0]
    else:
        cross = np.linalg.norm(np.cross(to_next, to_prev), axis=-1)
    return dot / np.abs(cross) / 2
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
    C = cotangent_weights(V, F)
    a = F[:, [1, 2, 0]].ravel()
    b = F[:, [2, 0, 1]].ravel()
    c = C.ravel()
    rows = np.concatenate([a, b, a, b])
    cols = np.concatenate([b, a, a, b])
    vals = np.concatenate([c, c, -c, -c])
    return sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
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
    n, d = V.shape
    a = F[:, [1, 2, 0]]
    b = F[:, [2, 0, 1]]
    per_tri = np.einsum("tk,tki,tkj->tij", np.asarray(C, dtype=float), V[b] - V[a], U[b] - U[a])
    S = np.zeros((n, d, d))
    np.add.at(S, F.ravel(), np.repeat(per_tri, 3, axis=0))
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
    return optimal_rotation(arap_covariances(V, U, F, C))
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
    # |e' - R e|^2 = e'.e' - 2 tr(R e e'^T) + tr(R e e^T R^T), summed over each cell:
    # all three sums are covariance stacks
    R = np.asarray(R, dtype=float)
    S_vu = arap_covariances(V, U, F, C)
    S_uu = arap_covariances(U, U, F, C)
    S_vv = arap_covariances(V, V, F, C)
    E = (np.trace(S_uu, axis1=1, axis2=2).sum()
         - 2.0 * np.einsum("nij,nji->", R, S_vu)
         + np.einsum("nij,njk,nik->", R, S_vv, R))
    return float(E)
''',
}
LOSES = set()
