NOTEBOOK = '03_arap'
DESCRIPTION = '04 einsum everywhere: Levi-Civita cross products, einsum covariances/energy/right-hand side, np.add.at with repeat'
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
    S = np.asarray(S, float)
    Us, sig, Vts = np.linalg.svd(S)
    sgn = np.sign(np.linalg.det(np.einsum("...ji,...kj->...ik", Vts, Us)))
    Vts = Vts.copy()
    Vts[..., -1, :] *= sgn[..., None]
    return np.einsum("...ji,...kj->...ik", Vts, Us)
''',
    'cotangent_weights': r'''import numpy as np


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
    P = V[F]
    a = P[:, [1, 2, 0]] - P
    b = P[:, [2, 0, 1]] - P
    dot = np.einsum("tki,tki->tk", a, b)
    if V.shape[1] == 2:
        eps = np.array([[0.0, 1.0], [-1.0, 0.0]])
        cross = np.abs(np.einsum("tki,ij,tkj->tk", a, eps, b))
    else:
        eps = np.zeros((3, 3, 3))
        eps[0, 1, 2] = eps[1, 2, 0] = eps[2, 0, 1] = 1.0
        eps[0, 2, 1] = eps[2, 1, 0] = eps[1, 0, 2] = -1.0
        cr = np.einsum("ijk,tnj,tnk->tni", eps, a, b)
        cross = np.sqrt(np.einsum("tni,tni->tn", cr, cr))
    return 0.5 * dot / cross
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
    n = len(V)
    F = np.asarray(F)
    C = cotangent_weights(V, F)
    I = np.hstack([F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel()])
    J = np.hstack([F[:, [2, 0, 1]].ravel(), F[:, [1, 2, 0]].ravel()])
    X = np.hstack([C.ravel(), C.ravel()])
    diag = np.bincount(I, weights=X, minlength=n)
    return sp.coo_matrix((np.hstack([X, -diag]), (np.hstack([I, np.arange(n)]), np.hstack([J, np.arange(n)]))),
                         shape=(n, n)).tocsr()
''',
    'arap_covariances': r'''import numpy as np


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
    V = np.asarray(V, float)
    U = np.asarray(U, float)
    F = np.asarray(F)
    n, d = V.shape
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    ep = U[F[:, [2, 0, 1]]] - U[F[:, [1, 2, 0]]]
    T = np.einsum("tk,tki,tkj->tij", C, e, ep)
    S = np.zeros((n, d, d))
    np.add.at(S, F.ravel(), np.repeat(T, 3, axis=0))
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
    return optimal_rotation(arap_covariances(V, U, F, C))
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
    V = np.asarray(V, float)
    U = np.asarray(U, float)
    F = np.asarray(F)
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    ep = U[F[:, [2, 0, 1]]] - U[F[:, [1, 2, 0]]]
    r = ep[:, None, :, :] - np.einsum("tcij,tkj->tcki", np.asarray(R, float)[F], e)
    return float(np.einsum("tk,tcki,tcki->", C, r, r))
''',
}
LOSES = set()
