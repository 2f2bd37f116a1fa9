NOTEBOOK = '03_arap'
DESCRIPTION = '07 physics student: half-edge arrays (tail, head, face), explicit list of half-edges per vertex cell, loops over cells'
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
    S = np.asarray(S, dtype=float)
    left, sv, right_h = np.linalg.svd(S)
    # reflection check: det(V U^T) = det(V) det(U)
    parity = np.linalg.det(left) * np.linalg.det(right_h)
    left = left.copy()
    left[..., :, -1] *= np.sign(parity)[..., None]
    # R = V (U D)^T, with D flipping the weakest direction when needed
    return np.matmul(np.swapaxes(right_h, -1, -2), np.swapaxes(left, -1, -2))
''',
    'cotangent_weights': r'''import numpy as np


def _opposite_edges(X, F):
    """Edge vectors e_k = x_{k+2} - x_{k+1}, the edge opposite corner k, running around the triangle."""
    return X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]


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
    F = np.asarray(F, dtype=np.int64)
    e = _opposite_edges(V, F)          # (f, 3, d), e_0 + e_1 + e_2 = 0
    e_next = np.roll(e, -1, axis=1)    # e_{k+1}
    e_prev = np.roll(e, -2, axis=1)    # e_{k+2}
    # double area from two consecutive edge vectors
    if V.shape[1] == 2:
        area2 = np.abs(e[:, 0, 0] * e[:, 1, 1] - e[:, 0, 1] * e[:, 1, 0])
    else:
        area2 = np.linalg.norm(np.cross(e[:, 0], e[:, 1]), axis=1)
    # the two edges leaving corner k are e_{k+2} and -e_{k+1}
    cot = -np.sum(e_next * e_prev, axis=2) / area2[:, None]
    return 0.5 * cot
''',
    'cotangent_laplacian': r'''import numpy as np
from scipy import sparse


def _half_edges(F):
    """Half-edge h = 3t + k runs from tail F[t,(k+1)%3] to head F[t,(k+2)%3] (opposite corner k)."""
    F = np.asarray(F, dtype=np.int64)
    tail = F[:, [1, 2, 0]].ravel()
    head = F[:, [2, 0, 1]].ravel()
    face = np.repeat(np.arange(len(F)), 3)
    return tail, head, face


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
    tail, head, _ = _half_edges(F)
    w = cotangent_weights(V, F).ravel()
    # each half-edge carries its triangle's weight; the twin direction comes from the transpose
    A = sparse.coo_matrix((w, (tail, head)), shape=(n, n)).tocsr()
    A = A + A.T
    degree = np.asarray(A.sum(axis=0)).ravel()
    return (A - sparse.diags(degree)).tocsr()
''',
    'arap_covariances': r'''import numpy as np


def _cells(F, n):
    """For every vertex the half-edges of the triangles around it (spokes and rims)."""
    cells = [[] for _ in range(n)]
    for t, tri in enumerate(np.asarray(F, dtype=np.int64)):
        hes = [3 * t, 3 * t + 1, 3 * t + 2]
        for v in tri:
            cells[v].extend(hes)
    return [np.array(c, dtype=np.int64) for c in cells]


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
    n, d = V.shape
    tail, head, _ = _half_edges(F)
    e = V[head] - V[tail]
    e_def = U[head] - U[tail]
    w = np.asarray(C, dtype=float).ravel()
    S = np.zeros((n, d, d))
    for i, cell in enumerate(_cells(F, n)):
        S[i] = (w[cell, None] * e[cell]).T @ e_def[cell]
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
    S = arap_covariances(V, U, F, C)
    return optimal_rotation(S)
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    R = np.asarray(R, dtype=float)
    tail, head, _ = _half_edges(F)
    e = V[head] - V[tail]
    e_def = U[head] - U[tail]
    w = np.asarray(C, dtype=float).ravel()
    energy = 0.0
    for i, cell in enumerate(_cells(F, len(V))):
        residual = e_def[cell] - e[cell] @ R[i].T
        energy += np.sum(w[cell] * np.sum(residual * residual, axis=1))
    return float(energy)
''',
}
LOSES = set()
