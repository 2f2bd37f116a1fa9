NOTEBOOK = "03_arap"
DESCRIPTION = "block-partition student: permutes the Laplacian into [free | handle] blocks with a permutation matrix and eliminates the handle columns explicitly; per-vertex cell lists"
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
    A, s, Bh = np.linalg.svd(S)
    d = S.shape[-1]
    # det(V U^T) = det(V) det(U)
    sgn = np.linalg.det(A) * np.linalg.det(Bh)
    Dg = np.concatenate([np.ones(S.shape[:-2] + (d - 1,)), np.sign(sgn)[..., None]], axis=-1)
    return np.einsum("...ji,...j,...kj->...ik", Bh, Dg, A)
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
    X = np.asarray(V, dtype=float)
    T = np.asarray(F)
    if X.shape[1] == 2:
        X = np.c_[X, np.zeros(len(X))]
    A = X[T[:, 0]]
    B = X[T[:, 1]]
    Cc = X[T[:, 2]]
    twice_area = np.linalg.norm(np.cross(B - A, Cc - A), axis=1)
    cot0 = np.sum((B - A) * (Cc - A), axis=1) / twice_area
    cot1 = np.sum((Cc - B) * (A - B), axis=1) / twice_area
    cot2 = np.sum((A - Cc) * (B - Cc), axis=1) / twice_area
    return 0.5 * np.column_stack((cot0, cot1, cot2))
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
    T = np.asarray(F)
    n = len(V)
    W = cotangent_weights(V, T)
    # edge (1,2) gets W[:,0], (2,0) gets W[:,1], (0,1) gets W[:,2]
    i = T[:, [1, 2, 0]].flatten()
    j = T[:, [2, 0, 1]].flatten()
    c = W.flatten()
    K = sp.coo_matrix((c, (i, j)), shape=(n, n)).tocsr()
    K = K + K.T
    D = sp.diags(np.asarray(K.sum(axis=0)).flatten())
    return (K - D).tocsr()
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
    X = np.asarray(V, dtype=float)
    Y = np.asarray(U, dtype=float)
    T = np.asarray(F)
    W = np.asarray(C, dtype=float)
    n, d = X.shape
    i = T[:, [1, 2, 0]]
    j = T[:, [2, 0, 1]]
    Ex = X[i] - X[j]
    Ey = Y[i] - Y[j]
    cellpart = np.einsum("tk,tka,tkb->tab", W, Ex, Ey)
    # cell of vertex v = the triangles around v
    order = np.argsort(T.flatten(), kind="stable")
    tri_of_corner = order // 3
    counts = np.bincount(T.flatten(), minlength=n)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    S = np.zeros((n, d, d))
    for v in range(n):
        S[v] = cellpart[tri_of_corner[starts[v]:starts[v] + counts[v]]].sum(axis=0)
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
    X = np.asarray(V, dtype=float)
    Y = np.asarray(U, dtype=float)
    T = np.asarray(F)
    W = np.asarray(C, dtype=float)
    Rs = np.asarray(R, dtype=float)
    i = T[:, [1, 2, 0]]
    j = T[:, [2, 0, 1]]
    Ex = X[i] - X[j]
    Ey = Y[i] - Y[j]
    E = 0.0
    for corner in range(3):
        Ri = Rs[T[:, corner]]
        diff = Ey - np.matmul(Ex, np.transpose(Ri, (0, 2, 1)))
        E += np.sum(W[:, :, None] * diff * diff)
    return float(E)
''',
}
LOSES = set()
