NOTEBOOK = "03_arap"
DESCRIPTION = "normal-equations student: builds the weighted edge-difference matrix G and solves G^T W G u = G^T W (R e) for the global step"
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
    S = np.asarray(S, dtype=np.float64)
    U_s, sv, Vt_s = np.linalg.svd(S)
    Ut = np.swapaxes(U_s, -1, -2)
    V_s = np.swapaxes(Vt_s, -1, -2)
    sign = np.sign(np.linalg.det(V_s @ Ut))
    V_s = V_s.copy()
    V_s[..., :, -1] = V_s[..., :, -1] * sign[..., None]
    return V_s @ Ut
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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    out = []
    for k in range(3):
        o = V[F[:, k]]
        a = V[F[:, (k + 1) % 3]] - o
        b = V[F[:, (k + 2) % 3]] - o
        if V.shape[1] == 2:
            s = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        else:
            s = np.sqrt((np.cross(a, b) ** 2).sum(axis=1))
        out.append((a * b).sum(axis=1) / (2.0 * s))
    return np.stack(out, axis=1)
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
    F = np.asarray(F, dtype=np.int64)
    n = np.shape(V)[0]
    f = F.shape[0]
    C = cotangent_weights(V, F)
    # G: one row per (triangle, edge), +1 at one end and -1 at the other
    heads = np.concatenate([F[:, (k + 1) % 3] for k in range(3)])
    tails = np.concatenate([F[:, (k + 2) % 3] for k in range(3)])
    m = 3 * f
    rows = np.concatenate([np.arange(m), np.arange(m)])
    G = sp.csr_matrix((np.r_[np.ones(m), -np.ones(m)], (rows, np.r_[heads, tails])), shape=(m, n))
    Wd = sp.diags(np.concatenate([C[:, k] for k in range(3)]))
    # u^T (G^T W G) u = sum c |u_i - u_j|^2, and that is -L
    return (-(G.T @ Wd @ G)).tocsr()
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
    V = np.asarray(V, dtype=np.float64)
    U = np.asarray(U, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=np.float64)
    n, d = V.shape
    f = F.shape[0]
    E = np.stack([V[F[:, (k + 1) % 3]] - V[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    Ep = np.stack([U[F[:, (k + 1) % 3]] - U[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    T = np.einsum("fk,fki,fkj->fij", C, E, Ep).reshape(f, d * d)
    # vertex-triangle incidence matrix, (n, f)
    A = sp.coo_matrix((np.ones(3 * f), (F.T.ravel(), np.tile(np.arange(f), 3))), shape=(n, f)).tocsr()
    return (A @ T).reshape(n, d, d)
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
    S = arap_covariances(V, U, F, C)
    R = optimal_rotation(S)
    return R
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
    V = np.asarray(V, dtype=np.float64)
    U = np.asarray(U, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    E = np.stack([V[F[:, (k + 1) % 3]] - V[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    Ep = np.stack([U[F[:, (k + 1) % 3]] - U[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    total = 0.0
    for c in range(3):
        RE = np.einsum("fij,fkj->fki", R[F[:, c]], E)
        total += np.einsum("fk,fki,fki->", C, Ep - RE, Ep - RE)
    return float(total)
''',
}
LOSES = set()
