NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 02: builds index/value arrays with np.stack / np.concatenate (triplets, incidence matrix) for every sparse assembly, detailed comments throughout.'
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
    S = np.asarray(S, dtype=np.float64)
    d = S.shape[-1]
    # np.linalg.svd works on the last two axes, so one (d, d) matrix and a stack
    # (k, d, d) go through exactly the same code
    U_svd, sigma, Vh = np.linalg.svd(S)
    V_svd = np.swapaxes(Vh, -1, -2)      # V~ (numpy returns its transpose)
    Ut_svd = np.swapaxes(U_svd, -1, -2)  # U~^T
    # det(V~ U~^T) is +1 or -1, one value per matrix of the stack
    det = np.linalg.det(V_svd @ Ut_svd)
    # D = diag(1, ..., 1, sign): a copy of the identity for every matrix
    D = np.broadcast_to(np.eye(d), S.shape).copy()
    D[..., -1, -1] = np.where(det < 0, -1.0, 1.0)
    # R = V~ D U~^T flips the direction of the smallest singular value if needed
    return V_svd @ D @ Ut_svd
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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    # positions of the three corners of every triangle, shape (f, 3, d)
    corners = V[F]
    # the two edge vectors leaving corner k: towards corner k+1 and towards corner k+2
    # (np.roll along the corner axis shifts "k" to "k+1" for all corners at once)
    to_next = np.roll(corners, -1, axis=1) - corners
    to_after = np.roll(corners, -2, axis=1) - corners
    # cot = (a . b) / |a x b|
    dot = np.sum(to_next * to_after, axis=2)
    if V.shape[1] == 2:
        # in 2D the cross product is the scalar a_x b_y - a_y b_x
        cross_len = np.abs(to_next[..., 0] * to_after[..., 1] - to_next[..., 1] * to_after[..., 0])
    else:
        cross_len = np.linalg.norm(np.cross(to_next, to_after), axis=2)
    # half of the cotangent, shape (f, 3)
    return 0.5 * dot / cross_len
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
    F = np.asarray(F, dtype=np.int64)
    n = np.shape(V)[0]
    C = cotangent_weights(V, F)
    # the edge opposite corner k goes from F[:, k+1] to F[:, k+2]; stacking the three
    # corners as columns gives (f, 3) arrays that line up with C, then flatten to 3f
    first = np.stack([F[:, 1], F[:, 2], F[:, 0]], axis=1).ravel()
    second = np.stack([F[:, 2], F[:, 0], F[:, 1]], axis=1).ravel()
    weight = C.ravel()
    # every edge in both directions so that the matrix comes out symmetric
    rows = np.concatenate([first, second])
    cols = np.concatenate([second, first])
    vals = np.concatenate([weight, weight])
    # converting coo -> csr adds up the duplicates (an interior edge gets a weight
    # from each of its two triangles)
    L = sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
    # diagonal: minus the row sums, so that every row sums to zero
    row_sums = np.asarray(L.sum(axis=1)).ravel()
    return (L - sp.diags(row_sums)).tocsr()
''',
    "arap_covariances": r'''import numpy as np
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
    n, d = V.shape
    f = F.shape[0]
    # edge opposite corner k, from F[:, k+1] to F[:, k+2], for rest and deformed
    # positions: (f, 3, d) each, same orientation for both
    rest_edges = np.roll(V[F], -2, axis=1) - np.roll(V[F], -1, axis=1)
    def_edges = np.roll(U[F], -2, axis=1) - np.roll(U[F], -1, axis=1)
    # per triangle: sum_k C[t, k] e_tk e'_tk^T, shape (f, d, d)
    M = np.einsum("tk,tka,tkb->tab", C, rest_edges, def_edges)
    # incidence matrix (n, f): entry (F[t, c], t) = 1 for the three corners c of t
    rows = F.ravel()                      # vertex of every (triangle, corner)
    cols = np.repeat(np.arange(f), 3)     # the triangle it belongs to
    A = sp.csr_matrix((np.ones(3 * f), (rows, cols)), shape=(n, f))
    # every vertex collects the matrices of its triangles: (n, f) @ (f, d*d)
    S = A @ M.reshape(f, d * d)
    return np.asarray(S).reshape(n, d, d)
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
    # local step: covariance of every cell, then its best rotation (whole stack at once)
    covariances = arap_covariances(V, U, F, C)
    return optimal_rotation(covariances)
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
    V = np.asarray(V, dtype=np.float64)
    U = np.asarray(U, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=np.float64)
    R = np.asarray(R, dtype=np.float64)
    # edges opposite every corner, (f, 3, d), rest and deformed
    rest_edges = np.roll(V[F], -2, axis=1) - np.roll(V[F], -1, axis=1)
    def_edges = np.roll(U[F], -2, axis=1) - np.roll(U[F], -1, axis=1)
    # rotations of the three corners of every triangle, (f, 3, d, d)
    corner_rot = R[F]
    # R_i e_tk for every (triangle t, corner i, edge k): (f, 3, 3, d)
    rotated = np.einsum("tiab,tkb->tika", corner_rot, rest_edges)
    # residuals e'_tk - R_i e_tk, the deformed edge broadcast over the corner axis
    resid = def_edges[:, np.newaxis, :, :] - rotated
    # weight every squared length with C[t, k] and sum over everything
    return float(np.einsum("tk,tika,tika->", C, resid, resid))
''',
}
LOSES = set()
