NOTEBOOK = '03_arap'
DESCRIPTION = '03 scipy engineer: sparse edge-difference operator D (3f x n), L = -D^T W D, incidence matrix for covariances, splu'
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
    S = np.asarray(S, dtype=np.float64)
    single = S.ndim == 2
    if single:
        S = S[np.newaxis]
    U, sv, Vh = np.linalg.svd(S)
    k, d, _ = S.shape
    D = np.tile(np.eye(d), (k, 1, 1))
    D[:, -1, -1] = np.linalg.det(np.matmul(U, Vh))
    R = np.matmul(np.matmul(Vh.transpose(0, 2, 1), D), U.transpose(0, 2, 1))
    return R[0] if single else R
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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    X = V[F]                                   # (f, 3, d) corner positions
    a = np.roll(X, -1, axis=1) - X             # to the next corner
    b = np.roll(X, -2, axis=1) - X             # to the corner after that
    if V.shape[1] == 2:
        a = np.concatenate([a, np.zeros(a.shape[:2] + (1,))], axis=2)
        b = np.concatenate([b, np.zeros(b.shape[:2] + (1,))], axis=2)
    dots = (a * b).sum(axis=2)
    sines = np.linalg.norm(np.cross(a, b), axis=2)
    return 0.5 * dots / sines
''',
    'cotangent_laplacian': r'''import numpy as np
import scipy.sparse as sp


def _difference_operator(F, n):
    """Sparse D, (3f, n): row 3t+k gives x[F[t,(k+2)%3]] - x[F[t,(k+1)%3]]."""
    F = np.asarray(F, dtype=np.int64)
    m = 3 * len(F)
    tail = F[:, [1, 2, 0]].ravel()
    head = F[:, [2, 0, 1]].ravel()
    r = np.arange(m)
    return sp.csr_matrix((np.r_[np.ones(m), -np.ones(m)], (np.r_[r, r], np.r_[head, tail])), shape=(m, n))


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
    n = np.shape(V)[0]
    D = _difference_operator(F, n)
    W = sp.diags(cotangent_weights(V, F).ravel())
    # -L is the stiffness matrix D^T W D
    return (-(D.T @ W @ D)).tocsr()
''',
    'arap_covariances': r'''import numpy as np
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
    n, d = V.shape
    f = len(F)
    D = _difference_operator(F, n)
    E0 = (D @ V).reshape(f, 3, d)
    E1 = (D @ U).reshape(f, 3, d)
    w = np.asarray(C, dtype=np.float64)[:, :, None, None]
    T = (w * E0[:, :, :, None] * E1[:, :, None, :]).sum(axis=1)    # (f, d, d)
    A = sp.csr_matrix((np.ones(3 * f), (F.ravel(), np.repeat(np.arange(f), 3))), shape=(n, f))
    return np.asarray(A @ T.reshape(f, d * d)).reshape(n, d, d)
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
    V = np.asarray(V, dtype=np.float64)
    U = np.asarray(U, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    R = np.asarray(R, dtype=np.float64)
    n, d = V.shape
    f = len(F)
    D = _difference_operator(F, n)
    E0 = (D @ V).reshape(f, 3, d)
    E1 = (D @ U).reshape(f, 3, d)
    total = 0.0
    for c in range(3):
        Rc = R[F[:, c]]                                   # rotation of corner c, (f, d, d)
        res = E1 - np.matmul(E0, Rc.transpose(0, 2, 1))   # rows: e' - R_c e
        total += np.sum(np.asarray(C) * (res ** 2).sum(axis=2))
    return float(total)
''',
}
LOSES = set()
