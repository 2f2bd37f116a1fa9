NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 07: handles 2D and 3D separately with if/else branches on the dimension (explicit 2x2 formulas in 2D, cross products in 3D), lists of triplets for the Laplacian.'
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
    S = np.asarray(S, dtype=float)
    if S.ndim == 2:
        Us, sv, Vts = np.linalg.svd(S)
        R = Vts.T @ Us.T
        if np.linalg.det(R) < 0:
            if S.shape[0] == 2:
                Dm = np.diag([1.0, -1.0])
            else:
                Dm = np.diag([1.0, 1.0, -1.0])
            R = Vts.T @ Dm @ Us.T
        return R
    else:
        Us, sv, Vts = np.linalg.svd(S)
        Vs = np.transpose(Vts, (0, 2, 1))
        UsT = np.transpose(Us, (0, 2, 1))
        dets = np.linalg.det(Vs @ UsT)
        if S.shape[1] == 2:
            Dm = np.zeros((len(S), 2, 2))
            Dm[:, 0, 0] = 1.0
            Dm[:, 1, 1] = dets
        else:
            Dm = np.zeros((len(S), 3, 3))
            Dm[:, 0, 0] = 1.0
            Dm[:, 1, 1] = 1.0
            Dm[:, 2, 2] = dets
        return Vs @ Dm @ UsT
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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F, dtype=int)
    C = np.zeros((F.shape[0], 3))
    for k in range(3):
        p = V[F[:, k]]
        a = V[F[:, (k + 1) % 3]] - p
        b = V[F[:, (k + 2) % 3]] - p
        if V.shape[1] == 2:
            dot = a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]
            cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        else:
            dot = a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]
            cx = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
            cy = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
            cz = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
            cross = np.sqrt(cx ** 2 + cy ** 2 + cz ** 2)
        C[:, k] = 0.5 * dot / cross
    return C
''',
    "cotangent_laplacian": r'''import numpy as np
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
    F = np.asarray(F, dtype=int)
    n = len(V)
    C = cotangent_weights(V, F)
    I, J, X = [], [], []
    for k in range(3):
        i = F[:, (k + 1) % 3]
        j = F[:, (k + 2) % 3]
        I += [i, j]
        J += [j, i]
        X += [C[:, k], C[:, k]]
    I = np.hstack(I)
    J = np.hstack(J)
    X = np.hstack(X)
    diag = np.bincount(I, weights=X, minlength=n)
    I = np.hstack([I, np.arange(n)])
    J = np.hstack([J, np.arange(n)])
    X = np.hstack([X, -diag])
    return sp.coo_matrix((X, (I, J)), shape=(n, n)).tocsr()
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F, dtype=int)
    C = np.asarray(C, dtype=float)
    n, dim = V.shape
    if dim == 2:
        M = np.zeros((len(F), 2, 2))
    else:
        M = np.zeros((len(F), 3, 3))
    for k in range(3):
        e = V[F[:, (k + 2) % 3]] - V[F[:, (k + 1) % 3]]
        ed = U[F[:, (k + 2) % 3]] - U[F[:, (k + 1) % 3]]
        w = C[:, k]
        if dim == 2:
            M[:, 0, 0] += w * e[:, 0] * ed[:, 0]
            M[:, 0, 1] += w * e[:, 0] * ed[:, 1]
            M[:, 1, 0] += w * e[:, 1] * ed[:, 0]
            M[:, 1, 1] += w * e[:, 1] * ed[:, 1]
        else:
            M += w[:, None, None] * e[:, :, None] * ed[:, None, :]
    S = np.zeros((n, dim, dim))
    for k in range(3):
        np.add.at(S, F[:, k], M)
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
    S = arap_covariances(V, U, F, C)
    R = optimal_rotation(S)
    return R
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F, dtype=int)
    C = np.asarray(C, dtype=float)
    R = np.asarray(R, dtype=float)
    dim = V.shape[1]
    E = 0.0
    for k in range(3):
        e = V[F[:, (k + 2) % 3]] - V[F[:, (k + 1) % 3]]
        ed = U[F[:, (k + 2) % 3]] - U[F[:, (k + 1) % 3]]
        for c in range(3):
            Rc = R[F[:, c]]
            if dim == 2:
                rx = ed[:, 0] - (Rc[:, 0, 0] * e[:, 0] + Rc[:, 0, 1] * e[:, 1])
                ry = ed[:, 1] - (Rc[:, 1, 0] * e[:, 0] + Rc[:, 1, 1] * e[:, 1])
                sq = rx ** 2 + ry ** 2
            else:
                r = ed - np.matmul(Rc, e[:, :, None])[:, :, 0]
                sq = np.sum(r ** 2, axis=1)
            E += np.sum(C[:, k] * sq)
    return float(E)
''',
}
LOSES = set()
