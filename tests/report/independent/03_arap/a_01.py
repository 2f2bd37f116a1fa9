NOTEBOOK = '03_arap'
DESCRIPTION = '01 maths undergraduate: small documented helpers, edges opposite corners, energy via the expanded square and traces'
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
    U_, sigma, Vt = np.linalg.svd(S)
    V_ = np.swapaxes(Vt, -1, -2).copy()
    Ut = np.swapaxes(U_, -1, -2)
    # det(V U^T) is +1 or -1; when it is -1 we flip the direction belonging to the smallest sigma
    s = np.where(np.linalg.det(V_ @ Ut) < 0, -1.0, 1.0)
    V_[..., :, -1] *= s[..., np.newaxis]
    return V_ @ Ut
''',
    'cotangent_weights': r'''import numpy as np


def _cross_norm(a, b):
    """Length of a x b for rows of vectors; in the plane a x b is the number a_x b_y - a_y b_x."""
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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    C = np.empty(F.shape, dtype=float)
    for k in range(3):
        apex = V[F[:, k]]
        a = V[F[:, (k + 1) % 3]] - apex
        b = V[F[:, (k + 2) % 3]] - apex
        # cot = cos / sin = (a . b) / |a x b|
        C[:, k] = 0.5 * np.sum(a * b, axis=1) / _cross_norm(a, b)
    return C
''',
    'cotangent_laplacian': r'''import numpy as np
import scipy.sparse as sp


def _edge_endpoints(F):
    """The endpoints (j, k) of the edge opposite every corner, as two (f, 3) index arrays."""
    F = np.asarray(F)
    return F[:, [1, 2, 0]], F[:, [2, 0, 1]]


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
    C = cotangent_weights(V, F)
    n = len(V)
    j, k = _edge_endpoints(F)
    rows = np.concatenate([j.ravel(), k.ravel()])
    cols = np.concatenate([k.ravel(), j.ravel()])
    vals = np.concatenate([C.ravel(), C.ravel()])
    off_diagonal = sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
    row_sums = np.asarray(off_diagonal.sum(axis=1)).ravel()
    return off_diagonal - sp.diags(row_sums)
''',
    'arap_covariances': r'''import numpy as np


def _edge_vectors(X, F):
    """e[t, k] = X[j] - X[i] for the edge (i, j) opposite corner k of triangle t, shape (f, 3, d)."""
    i, j = _edge_endpoints(F)
    return X[j] - X[i]


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
    F = np.asarray(F)
    C = np.asarray(C, dtype=float)
    n, d = V.shape
    e_rest = _edge_vectors(V, F)
    e_def = _edge_vectors(U, F)
    # one matrix per triangle, the same for its three corners
    M = np.einsum("tk,tka,tkb->tab", C, e_rest, e_def)
    S = np.zeros((n, d, d))
    for corner in range(3):
        np.add.at(S, F[:, corner], M)
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F)
    C = np.asarray(C, dtype=float)
    R = np.asarray(R, dtype=float)
    e_rest = _edge_vectors(V, F)
    e_def = _edge_vectors(U, F)
    # ||e' - R e||^2 = ||e'||^2 + ||e||^2 - 2 tr(R e e'^T), summed over the three corner rotations
    squares = np.sum(C * (np.sum(e_def ** 2, axis=2) + np.sum(e_rest ** 2, axis=2)))
    M = np.einsum("tk,tka,tkb->tab", C, e_rest, e_def)
    R_sum = R[F].sum(axis=1)
    cross_term = np.einsum("tab,tba->", R_sum, M)
    return float(3.0 * squares - 2.0 * cross_term)
''',
}
LOSES = set()
