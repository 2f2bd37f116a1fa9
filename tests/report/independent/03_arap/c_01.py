NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 01: functional style: list comprehensions, zip over per-matrix / per-triangle data, sums of generators, dict for the precomputed data.'
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
    mats = np.asarray(S, dtype=float)
    d = mats.shape[-1]
    flip = np.diag([1.0] * (d - 1) + [-1.0])

    def best(u, vt):
        r = vt.T @ u.T
        return r if np.linalg.det(r) > 0 else vt.T @ flip @ u.T

    stack = mats.reshape(-1, d, d)
    return np.array([best(u, vt) for u, _, vt in zip(*np.linalg.svd(stack))]).reshape(mats.shape)
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

    def cross_len(a, b):
        if a.shape[1] == 2:
            return np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        return np.linalg.norm(np.cross(a, b), axis=1)

    def half_cot(k):
        a, b = (V[F[:, (k + s) % 3]] - V[F[:, k]] for s in (1, 2))
        return 0.5 * np.einsum("ij,ij->i", a, b) / cross_len(a, b)

    return np.column_stack([half_cot(k) for k in range(3)])
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
    half = sum(sp.coo_matrix((C[:, k], (F[:, (k + 1) % 3], F[:, (k + 2) % 3])), shape=(n, n)) for k in range(3))
    W = (half + half.T).tocsr()
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()
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
    V, U, C = (np.asarray(X, dtype=float) for X in (V, U, C))
    F = np.asarray(F, dtype=int)
    d = V.shape[1]
    opp = [(F[:, (k + 1) % 3], F[:, (k + 2) % 3]) for k in range(3)]
    rest = np.stack([V[b] - V[a] for a, b in opp], axis=1)
    moved = np.stack([U[b] - U[a] for a, b in opp], axis=1)
    per_tri = np.array([sum(c * np.outer(e, e2) for c, e, e2 in zip(cs, es, e2s))
                        for cs, es, e2s in zip(C, rest, moved)]).reshape(-1, d, d)
    S = np.zeros((len(V), d, d))
    for corner in F.T:
        np.add.at(S, corner, per_tri)
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
    V, U, C, R = (np.asarray(X, dtype=float) for X in (V, U, C, R))
    F = np.asarray(F, dtype=int)

    def term(i, k):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        r = (U[b] - U[a]) - np.einsum("tij,tj->ti", R[F[:, i]], V[b] - V[a])
        return np.sum(C[:, k] * np.sum(r ** 2, axis=1))

    return float(sum(term(i, k) for i in range(3) for k in range(3)))
''',
}
LOSES = set()
