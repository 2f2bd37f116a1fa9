NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 03: thinks per vertex: one-ring neighbourhoods as Python dicts/sets (vertex -> triangles, vertex -> neighbour weights), loops over vertices.'
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
    S = np.array(S, dtype=float)
    single = S.ndim == 2
    if single:
        S = S[np.newaxis]
    R = np.empty_like(S)
    for i in range(S.shape[0]):
        u, sig, vt = np.linalg.svd(S[i])
        r = vt.T.dot(u.T)
        if np.linalg.det(r) < 0:
            u[:, -1] = -u[:, -1]
            r = vt.T.dot(u.T)
        R[i] = r
    if single:
        return R[0]
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
    V = np.array(V, dtype=float)
    F = np.array(F, dtype=int)
    C = np.zeros((len(F), 3))
    for t in range(len(F)):
        for k in range(3):
            i = F[t, k]
            j = F[t, (k + 1) % 3]
            l = F[t, (k + 2) % 3]
            a = V[j] - V[i]
            b = V[l] - V[i]
            if len(a) == 2:
                twice_area = abs(a[0] * b[1] - a[1] * b[0])
            else:
                twice_area = np.linalg.norm(np.cross(a, b))
            C[t, k] = 0.5 * a.dot(b) / twice_area
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
    F = np.array(F, dtype=int)
    n = len(V)
    C = cotangent_weights(V, F)
    # neighbours of every vertex with the summed weight of the edge
    ring = {i: {} for i in range(n)}
    for t in range(len(F)):
        for k in range(3):
            j = int(F[t, (k + 1) % 3])
            l = int(F[t, (k + 2) % 3])
            ring[j][l] = ring[j].get(l, 0.0) + C[t, k]
            ring[l][j] = ring[l].get(j, 0.0) + C[t, k]
    rows, cols, vals = [], [], []
    for i in ring:
        for j in ring[i]:
            rows.append(i)
            cols.append(j)
            vals.append(ring[i][j])
        rows.append(i)
        cols.append(i)
        vals.append(-sum(ring[i].values()))
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
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
    V = np.array(V, dtype=float)
    U = np.array(U, dtype=float)
    F = np.array(F, dtype=int)
    C = np.array(C, dtype=float)
    n, d = V.shape
    # triangles around every vertex
    tris_of = {i: set() for i in range(n)}
    for t in range(len(F)):
        for i in F[t]:
            tris_of[int(i)].add(t)
    # the matrix every triangle gives to each of its corners
    M = np.zeros((len(F), d, d))
    for k in range(3):
        e = V[F[:, (k + 2) % 3]] - V[F[:, (k + 1) % 3]]
        e2 = U[F[:, (k + 2) % 3]] - U[F[:, (k + 1) % 3]]
        M += C[:, k, None, None] * np.einsum("ti,tj->tij", e, e2)
    S = np.zeros((n, d, d))
    for i in range(n):
        cell = list(tris_of[i])
        S[i] = M[cell].sum(axis=0)
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
    V = np.array(V, dtype=float)
    U = np.array(U, dtype=float)
    F = np.array(F, dtype=int)
    C = np.array(C, dtype=float)
    R = np.array(R, dtype=float)
    n = len(V)
    tris_of = {i: [] for i in range(n)}
    for t in range(len(F)):
        for i in F[t]:
            tris_of[int(i)].append(t)
    E = 0.0
    for i in range(n):
        cell = np.array(tris_of[i], dtype=int)
        for k in range(3):
            j = F[cell, (k + 1) % 3]
            l = F[cell, (k + 2) % 3]
            diff = (U[l] - U[j]) - (V[l] - V[j]).dot(R[i].T)
            E += np.sum(C[cell, k] * np.sum(diff ** 2, axis=1))
    return float(E)
''',
}
LOSES = set()
