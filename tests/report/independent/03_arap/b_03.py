NOTEBOOK = "03_arap"
DESCRIPTION = "array-programming student: boolean masks for handles and reflections, np.bincount for every accumulation, np.roll for corners"
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
    S = np.asarray(S, float)
    u, s, vh = np.linalg.svd(S)
    R = np.swapaxes(u @ vh, -1, -2)
    flip = np.linalg.det(R) < 0
    if np.any(flip):
        vh = vh.copy()
        vh[flip, -1, :] *= -1
        R = np.swapaxes(u @ vh, -1, -2)
    return R
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
    V = np.asarray(V, float)
    F = np.asarray(F)
    X = V[F]                                  # (f, 3, d) corner positions
    a = np.roll(X, -1, axis=1) - X            # towards the next corner
    b = np.roll(X, -2, axis=1) - X            # towards the one after
    dots = (a * b).sum(-1)
    if V.shape[1] == 3:
        areas2 = np.linalg.norm(np.cross(a, b), axis=-1)
    else:
        areas2 = np.abs(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])
    return 0.5 * dots / areas2
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
    C = cotangent_weights(V, F).ravel()
    i = np.roll(F, -1, axis=1).ravel()
    j = np.roll(F, -2, axis=1).ravel()
    diag = -(np.bincount(i, C, minlength=n) + np.bincount(j, C, minlength=n))
    rows = np.r_[i, j, np.arange(n)]
    cols = np.r_[j, i, np.arange(n)]
    vals = np.r_[C, C, diag]
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
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
    V, U, C = np.asarray(V, float), np.asarray(U, float), np.asarray(C, float)
    F = np.asarray(F)
    n, d = V.shape
    E0 = V[np.roll(F, -2, axis=1)] - V[np.roll(F, -1, axis=1)]
    E1 = U[np.roll(F, -2, axis=1)] - U[np.roll(F, -1, axis=1)]
    St = np.einsum("tk,tki,tkj->tij", C, E0, E1).reshape(len(F), d * d)
    idx = F.ravel()
    flat = np.repeat(St, 3, axis=0)           # one copy per corner, in F.ravel() order
    S = np.stack([np.bincount(idx, flat[:, c], minlength=n) for c in range(d * d)], axis=1)
    return S.reshape(n, d, d)
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
    V, U, C, R = (np.asarray(x, float) for x in (V, U, C, R))
    F = np.asarray(F)
    E0 = V[np.roll(F, -2, axis=1)] - V[np.roll(F, -1, axis=1)]
    E1 = U[np.roll(F, -2, axis=1)] - U[np.roll(F, -1, axis=1)]
    RE = np.einsum("tcij,tkj->tcki", R[F], E0)     # corner c's rotation applied to edge k
    res = ((E1[:, None] - RE) ** 2).sum(-1)        # (f, corner, edge)
    return float((res * C[:, None, :]).sum())
''',
}
LOSES = set()
