NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 08: minimalist, fewest lines that work, no comments; fancy indexing with F[:, [1, 2, 0]], one einsum per step, tuple for the data.'
SOLUTIONS = {
    "optimal_rotation": r'''import numpy as np


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
    u, _, vt = np.linalg.svd(S)
    vt[..., -1, :] *= np.sign(np.linalg.det(u @ vt))[..., None]
    return np.swapaxes(u @ vt, -1, -2)
''',
    "cotangent_weights": r'''import numpy as np


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
    a = V[F[:, [1, 2, 0]]] - V[F]
    b = V[F[:, [2, 0, 1]]] - V[F]
    x = np.cross(np.pad(a, ((0, 0), (0, 0), (0, 3 - V.shape[1]))), np.pad(b, ((0, 0), (0, 0), (0, 3 - V.shape[1]))))
    return 0.5 * (a * b).sum(-1) / np.linalg.norm(x, axis=-1)
''',
    "cotangent_laplacian": r'''import scipy.sparse as sp


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
    i, j, n = F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel(), len(V)
    W = sp.coo_matrix((cotangent_weights(V, F).ravel(), (i, j)), (n, n)).tocsr()
    W = W + W.T
    return W - sp.diags(W.sum(1).A1)
''',
    "arap_covariances": r'''import numpy as np


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
    V, U = np.asarray(V, float), np.asarray(U, float)
    e = lambda X: X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]
    M = np.einsum("tk,tki,tkj->tij", C, e(V), e(U))
    S = np.zeros((len(V),) + M.shape[1:])
    np.add.at(S, F, M[:, None])
    return S
''',
    "arap_rotations": r'''def arap_rotations(V, U, F, C):
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
    "arap_energy": r'''import numpy as np


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
    V, U, R = np.asarray(V, float), np.asarray(U, float), np.asarray(R, float)
    e = lambda X: X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]
    r = e(U)[:, None] - np.einsum("tcij,tkj->tcki", R[F], e(V))
    return float(np.einsum("tk,tcki->", C, r ** 2))
''',
}
LOSES = set()
