NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 10: writes the energy and covariances with generators over (corner, edge) pairs and explicit norms via np.linalg.norm on stacked residual arrays; edge vectors stacked per triangle.'
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
    Uu, sig, Vh = np.linalg.svd(S)
    det_sign = np.linalg.det(np.einsum("...ji,...kj->...ik", Vh, Uu))
    Vh = Vh.copy()
    Vh[..., -1, :] = Vh[..., -1, :] * det_sign[..., np.newaxis]
    return np.einsum("...ji,...kj->...ik", Vh, Uu)
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
    F = np.asarray(F, dtype=np.int64)

    def corner(k):
        a = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        b = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        if V.shape[1] == 2:
            area2 = np.abs(np.linalg.det(np.stack((a, b), axis=-1)))
        else:
            area2 = np.linalg.norm(np.cross(a, b), axis=-1)
        return np.sum(a * b, axis=-1) / area2 / 2.0

    return np.stack(tuple(corner(k) for k in range(3)), axis=-1)
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
    n = np.asarray(V).shape[0]
    C = cotangent_weights(V, F)
    rows = np.hstack(tuple(F[:, (k + 1) % 3] for k in range(3)))
    cols = np.hstack(tuple(F[:, (k + 2) % 3] for k in range(3)))
    vals = np.hstack(tuple(C[:, k] for k in range(3)))
    off = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    off = off + off.transpose()
    return sp.csr_matrix(off - sp.diags(np.asarray(off.sum(axis=0)).ravel()))
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
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=float)
    n, d = V.shape
    rest = np.stack(tuple(V[F[:, (k + 2) % 3]] - V[F[:, (k + 1) % 3]] for k in range(3)), axis=1)
    now = np.stack(tuple(U[F[:, (k + 2) % 3]] - U[F[:, (k + 1) % 3]] for k in range(3)), axis=1)
    tri_S = sum(C[:, k, None, None] * rest[:, k, :, None] * now[:, k, None, :] for k in range(3))
    S = np.zeros((n, d, d))
    for k in range(3):
        np.add.at(S, F[:, k], tri_S)
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
    rotations = optimal_rotation(S)
    return rotations
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
    F = np.asarray(F, dtype=np.int64)
    C = np.asarray(C, dtype=float)
    R = np.asarray(R, dtype=float)
    rest = np.stack(tuple(V[F[:, (k + 2) % 3]] - V[F[:, (k + 1) % 3]] for k in range(3)), axis=1)
    now = np.stack(tuple(U[F[:, (k + 2) % 3]] - U[F[:, (k + 1) % 3]] for k in range(3)), axis=1)
    # residual of edge k against the rotation of corner i, stacked as (f, 3 edges, d)
    residuals = (now - np.einsum("tab,tkb->tka", R[F[:, i]], rest) for i in range(3))
    return float(sum(np.sum(C * np.linalg.norm(res, axis=-1) ** 2) for res in residuals))
''',
}
LOSES = set()
