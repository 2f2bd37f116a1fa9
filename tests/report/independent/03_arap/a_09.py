NOTEBOOK = '03_arap'
DESCRIPTION = '09 module style: many tiny private functions (_arr, _cot, _cross_len, _edges, _scatter, _mean_rot, ...), data as a dict'
SOLUTIONS = {
    'optimal_rotation': r'''import numpy as np


def _arr(X):
    return np.asarray(X, dtype=float)


def _T(A):
    return np.swapaxes(A, -1, -2)


def _sign_fix(u, vt):
    s = np.linalg.det(u) * np.linalg.det(vt)
    diag = np.ones(u.shape[:-1])
    diag[..., -1] = s
    return diag


def _diag(x):
    D = np.zeros(x.shape + x.shape[-1:])
    i = np.arange(x.shape[-1])
    D[..., i, i] = x
    return D


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
    u, _, vt = np.linalg.svd(_arr(S))
    return _T(vt) @ _diag(_sign_fix(u, vt)) @ _T(u)
''',
    'cotangent_weights': r'''import numpy as np


def _idx(F):
    return np.asarray(F, dtype=np.int64)


def _pts(V, F, k):
    return V[F[:, k % 3]]


def _dot(a, b):
    return np.sum(a * b, axis=-1)


def _cross_len(a, b):
    if a.shape[-1] == 2:
        return np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    return np.linalg.norm(np.cross(a, b), axis=-1)


def _cot(a, b):
    return _dot(a, b) / _cross_len(a, b)


def _corner_cot(V, F, k):
    o = _pts(V, F, k)
    return _cot(_pts(V, F, k + 1) - o, _pts(V, F, k + 2) - o)


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
    V, F = _arr(V), _idx(F)
    return 0.5 * np.column_stack([_corner_cot(V, F, k) for k in range(3)])
''',
    'cotangent_laplacian': r'''import numpy as np
import scipy.sparse as sp


def _tails(F):
    return _idx(F)[:, [1, 2, 0]]


def _heads(F):
    return _idx(F)[:, [2, 0, 1]]


def _sym_coo(i, j, v, n):
    return sp.coo_matrix((np.r_[v, v], (np.r_[i, j], np.r_[j, i])), shape=(n, n)).tocsr()


def _with_diag(A):
    return A - sp.diags(np.ravel(A.sum(axis=1)))


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
    W = _sym_coo(_tails(F).ravel(), _heads(F).ravel(), cotangent_weights(V, F).ravel(), len(V))
    return _with_diag(W)
''',
    'arap_covariances': r'''import numpy as np


def _edges(X, F):
    X = _arr(X)
    return X[_heads(F)] - X[_tails(F)]


def _tri_mats(C, e, ep):
    return (_arr(C)[:, :, None, None] * e[:, :, :, None] * ep[:, :, None, :]).sum(axis=1)


def _scatter(n, F, M):
    out = np.zeros((n,) + M.shape[1:])
    for k in range(3):
        np.add.at(out, _idx(F)[:, k], M)
    return out


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
    return _scatter(len(V), F, _tri_mats(C, _edges(V, F), _edges(U, F)))
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


def _rotate(Rs, e):
    return np.einsum("tij,tkj->tki", Rs, e)


def _sqnorm(x):
    return _dot(x, x)


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
    e, ep, R, F = _edges(V, F), _edges(U, F), _arr(R), _idx(F)
    return float(sum(np.sum(_arr(C) * _sqnorm(ep - _rotate(R[F[:, c]], e))) for c in range(3)))
''',
}
LOSES = set()
