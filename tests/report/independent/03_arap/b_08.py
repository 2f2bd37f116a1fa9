NOTEBOOK = "03_arap"
DESCRIPTION = "cautious student: shape asserts everywhere, explicit float64/int64 conversions, dataclass-free dict, splu"
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
    S = np.asarray(S, dtype=np.float64)
    assert S.ndim in (2, 3) and S.shape[-1] == S.shape[-2], "S must be (d, d) or (k, d, d)"
    d = S.shape[-1]
    U_svd, sing, Vt_svd = np.linalg.svd(S)
    V_svd = np.swapaxes(Vt_svd, -1, -2)
    Ut_svd = np.swapaxes(U_svd, -1, -2)
    det = np.linalg.det(V_svd @ Ut_svd)
    D = np.zeros(S.shape, dtype=np.float64)
    for a in range(d - 1):
        D[..., a, a] = 1.0
    D[..., d - 1, d - 1] = det
    R = V_svd @ D @ Ut_svd
    assert R.shape == S.shape
    return R
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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    assert V.ndim == 2 and V.shape[1] in (2, 3)
    assert F.ndim == 2 and F.shape[1] == 3
    if V.shape[1] == 2:
        # lift to 3D so that one cross product works for both cases
        V = np.hstack([V, np.zeros((V.shape[0], 1), dtype=np.float64)])
    C = np.zeros(F.shape, dtype=np.float64)
    for k in range(3):
        corner = V[F[:, k]]
        a = V[F[:, (k + 1) % 3]] - corner
        b = V[F[:, (k + 2) % 3]] - corner
        cos_part = np.einsum("ij,ij->i", a, b)
        sin_part = np.linalg.norm(np.cross(a, b), axis=1)
        assert np.all(sin_part > 0.0), "degenerate triangle"
        C[:, k] = 0.5 * cos_part / sin_part
    assert C.shape == (F.shape[0], 3)
    return C
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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    n = V.shape[0]
    C = cotangent_weights(V, F)
    assert C.shape == F.shape
    I = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    J = np.concatenate([F[:, 2], F[:, 0], F[:, 1]])
    W = np.concatenate([C[:, 0], C[:, 1], C[:, 2]])
    A = sp.coo_matrix((W, (I, J)), shape=(n, n))
    A = (A + A.T).tocsr()
    row_sums = np.asarray(A.sum(axis=1), dtype=np.float64).reshape(-1)
    L = (A - sp.diags(row_sums, 0, shape=(n, n))).tocsr()
    assert L.shape == (n, n)
    return L
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
    V = np.asarray(V, dtype=np.float64)
    U = np.asarray(U, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=np.float64)
    assert V.shape == U.shape
    assert C.shape == F.shape
    n, d = V.shape
    f = F.shape[0]
    opp_a = np.stack([F[:, 1], F[:, 2], F[:, 0]], axis=1)
    opp_b = np.stack([F[:, 2], F[:, 0], F[:, 1]], axis=1)
    e_rest = V[opp_b] - V[opp_a]
    e_def = U[opp_b] - U[opp_a]
    assert e_rest.shape == (f, 3, d)
    S_tri = np.einsum("fk,fki,fkj->fij", C, e_rest, e_def)
    S = np.zeros((n, d, d), dtype=np.float64)
    for k in range(3):
        np.add.at(S, F[:, k], S_tri)
    assert S.shape == (n, d, d)
    return S
''',
    "arap_rotations": '''import numpy as np


def arap_rotations(V, U, F, C):
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
    assert R.shape == S.shape
    return np.asarray(R, dtype=np.float64)
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
    V = np.asarray(V, dtype=np.float64)
    U = np.asarray(U, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    n, d = V.shape
    assert U.shape == (n, d) and R.shape == (n, d, d) and C.shape == F.shape
    opp_a = np.stack([F[:, 1], F[:, 2], F[:, 0]], axis=1)
    opp_b = np.stack([F[:, 2], F[:, 0], F[:, 1]], axis=1)
    e_rest = V[opp_b] - V[opp_a]                    # (f, 3, d), index = edge
    e_def = U[opp_b] - U[opp_a]
    R_corner = R[F]                                  # (f, 3, d, d), index = corner
    rotated = np.einsum("fcij,fej->fcei", R_corner, e_rest)   # (f, corner, edge, d)
    residual = e_def[:, np.newaxis, :, :] - rotated
    assert residual.shape == (F.shape[0], 3, 3, d)
    E = np.einsum("fe,fcei,fcei->", C, residual, residual)
    return float(E)
''',
}
LOSES = set()
