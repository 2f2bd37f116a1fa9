NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 06: scipy-heavy; factorizes (-L)_ff with scipy.sparse.linalg.splu and keeps the SuperLU object in a small class, solves all coordinates at once with lu.solve.'
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
    U, s, Vt = np.linalg.svd(S)
    R = np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)
    bad = np.linalg.det(R) < 0
    if np.any(bad):
        if S.ndim == 2:
            Vt[-1, :] *= -1.0
        else:
            Vt[bad, -1, :] *= -1.0
        R = np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)
    return R
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
    X = np.asarray(V, dtype=float)
    T = np.asarray(F, dtype=np.int64)
    out = np.zeros((T.shape[0], 3))
    for k in range(3):
        o = X[T[:, k]]
        u = X[T[:, (k + 1) % 3]] - o
        v = X[T[:, (k + 2) % 3]] - o
        if X.shape[1] == 3:
            sin_part = np.linalg.norm(np.cross(u, v), axis=1)
        else:
            sin_part = np.abs(np.linalg.det(np.stack([u, v], axis=1)))
        out[:, k] = np.einsum("ij,ij->i", u, v) / sin_part
    return 0.5 * out
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
    T = np.asarray(F, dtype=np.int64)
    n = np.shape(V)[0]
    W = cotangent_weights(V, T)
    L = sp.csc_matrix((n, n))
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        L = L + sp.csc_matrix((W[:, k], (i, j)), shape=(n, n)) + sp.csc_matrix((W[:, k], (j, i)), shape=(n, n))
    L = L - sp.diags(np.ravel(L.sum(axis=0)), format="csc")
    return L
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
    X = np.asarray(V, dtype=float)
    Y = np.asarray(U, dtype=float)
    T = np.asarray(F, dtype=np.int64)
    W = np.asarray(C, dtype=float)
    n, d = X.shape
    S = np.zeros((n, d, d))
    tri = np.zeros((T.shape[0], d, d))
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        tri += np.einsum("t,ta,tb->tab", W[:, k], X[i] - X[j], Y[i] - Y[j])
    for c in range(3):
        np.add.at(S, T[:, c], tri)
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
    X = np.asarray(V, dtype=float)
    Y = np.asarray(U, dtype=float)
    T = np.asarray(F, dtype=np.int64)
    W = np.asarray(C, dtype=float)
    Rot = np.asarray(R, dtype=float)
    energy = 0.0
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        e = X[i] - X[j]
        e_def = Y[i] - Y[j]
        for c in range(3):
            res = e_def - np.einsum("tab,tb->ta", Rot[T[:, c]], e)
            energy += np.dot(W[:, k], np.einsum("ta,ta->t", res, res))
    return float(energy)
''',
}
LOSES = set()
