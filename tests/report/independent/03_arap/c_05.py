NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 05: normalizes every input through small helpers (_as_float, _as_int, _opposite_edges, _check_handles) defined at the top of each cell; SimpleNamespace for the data.'
SOLUTIONS = {
    "optimal_rotation": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


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
    S = _as_float(S)
    shape = S.shape
    d = shape[-1]
    S3 = S.reshape(-1, d, d)
    U, s, Vt = np.linalg.svd(S3)
    V = Vt.transpose(0, 2, 1)
    Ut = U.transpose(0, 2, 1)
    D = np.zeros_like(S3)
    idx = np.arange(d)
    D[:, idx, idx] = 1.0
    D[:, -1, -1] = np.linalg.det(V @ Ut)
    return (V @ D @ Ut).reshape(shape)
''',
    "cotangent_weights": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _as_int(x):
    return np.asarray(x, dtype=np.int64)


def _cross_norm(a, b):
    if a.shape[-1] == 2:
        return np.abs(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])
    return np.linalg.norm(np.cross(a, b), axis=-1)


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
    V, F = _as_float(V), _as_int(F)
    # E[:, k] = edge opposite corner k = v_{k+2} - v_{k+1}
    E = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    # at corner k the two edges leaving it are -E[:, k+1] and E[:, k+2]
    E1 = E[:, [1, 2, 0]]
    E2 = E[:, [2, 0, 1]]
    dots = -np.sum(E1 * E2, axis=-1)
    twice_area = _cross_norm(E[:, 0], E[:, 1])
    return 0.5 * dots / twice_area[:, None]
''',
    "cotangent_laplacian": r'''import numpy as np
import scipy.sparse as sp


def _as_int(x):
    return np.asarray(x, dtype=np.int64)


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
    F = _as_int(F)
    n = len(V)
    C = cotangent_weights(V, F)
    I = F[:, [1, 2, 0]].ravel()
    J = F[:, [2, 0, 1]].ravel()
    W = sp.csr_matrix((np.r_[C.ravel(), C.ravel()], (np.r_[I, J], np.r_[J, I])), shape=(n, n))
    return sp.csr_matrix(W - sp.diags(W.sum(axis=1).A1))
''',
    "arap_covariances": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _as_int(x):
    return np.asarray(x, dtype=np.int64)


def _opposite_edges(X, F):
    return X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]


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
    V, U, C = _as_float(V), _as_float(U), _as_float(C)
    F = _as_int(F)
    n, d = V.shape
    Er = _opposite_edges(V, F)
    Ed = _opposite_edges(U, F)
    M = np.einsum("fk,fka,fkb->fab", C, Er, Ed)
    S = np.zeros((n, d, d))
    np.add.at(S, F.T.ravel(), np.tile(M, (3, 1, 1)))
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
    return optimal_rotation(S)
''',
    "arap_energy": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _as_int(x):
    return np.asarray(x, dtype=np.int64)


def _opposite_edges(X, F):
    return X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]


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
    V, U, C, R = _as_float(V), _as_float(U), _as_float(C), _as_float(R)
    F = _as_int(F)
    Er = _opposite_edges(V, F)
    Ed = _opposite_edges(U, F)
    total = 0.0
    for i in range(3):
        Ri = R[F[:, i]]
        diff = Ed - np.einsum("fab,fkb->fka", Ri, Er)
        total += np.sum(C * np.sum(diff * diff, axis=2))
    return float(total)
''',
}
LOSES = set()
