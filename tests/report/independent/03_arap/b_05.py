NOTEBOOK = "03_arap"
DESCRIPTION = "loop student who builds sparse matrices with scipy.sparse.lil_matrix entry by entry; per-triangle python loops"
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
    if S.ndim == 2:
        U_, s, Vh = np.linalg.svd(S)
        R = Vh.T @ U_.T
        if np.linalg.det(R) < 0:
            Vh[-1, :] = -Vh[-1, :]
            R = Vh.T @ U_.T
        return R
    out = np.empty_like(S)
    for i in range(S.shape[0]):
        out[i] = optimal_rotation(S[i])
    return out
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
    C = np.zeros((len(F), 3))
    for t in range(len(F)):
        for k in range(3):
            p = V[F[t, k]]
            a = V[F[t, (k + 1) % 3]] - p
            b = V[F[t, (k + 2) % 3]] - p
            if len(p) == 2:
                cr = abs(a[0] * b[1] - a[1] * b[0])
            else:
                cr = np.linalg.norm(np.cross(a, b))
            C[t, k] = 0.5 * np.dot(a, b) / cr
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
    C = cotangent_weights(V, F)
    L = sp.lil_matrix((n, n))
    for t in range(len(F)):
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            c = C[t, k]
            L[i, j] += c
            L[j, i] += c
            L[i, i] -= c
            L[j, j] -= c
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
    n, d = V.shape
    S = np.zeros((n, d, d))
    for t in range(len(F)):
        St = np.zeros((d, d))
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            St += C[t][k] * np.outer(V[i] - V[j], U[i] - U[j])
        for corner in F[t]:
            S[corner] += St
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
    S = arap_covariances(V, U, F, C)
    return optimal_rotation(S)
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
    R = np.asarray(R, dtype=float)
    E = 0.0
    for t in range(len(F)):
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            e = V[i] - V[j]
            e2 = U[i] - U[j]
            for corner in F[t]:
                r = e2 - R[corner] @ e
                E += C[t][k] * np.dot(r, r)
    return float(E)
''',
}
LOSES = set()
