NOTEBOOK = '03_arap'
DESCRIPTION = '08 puts everything in dicts: geometry helper dicts, arap_precompute stores edges, scatter indices, identity stack and factorization'
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
    svd = dict(zip(("U", "s", "Vt"), np.linalg.svd(S)))
    Vm = np.swapaxes(svd["Vt"], -1, -2)
    Ut = np.swapaxes(svd["U"], -1, -2)
    flip = np.ones(S.shape[-1])
    flip[-1] = -1.0
    candidates = {"plain": Vm @ Ut, "flipped": (Vm * flip) @ Ut}
    bad = np.linalg.det(candidates["plain"]) < 0
    return np.where(np.asarray(bad)[..., None, None], candidates["flipped"], candidates["plain"])
''',
    'cotangent_weights': r'''import numpy as np


def _geometry(V, F):
    g = {"V": np.asarray(V, dtype=float), "F": np.asarray(F, dtype=np.int64)}
    g["corners"] = g["V"][g["F"]]
    g["to_next"] = g["corners"][:, [1, 2, 0]] - g["corners"]
    g["to_prev"] = g["corners"][:, [2, 0, 1]] - g["corners"]
    g["dot"] = np.sum(g["to_next"] * g["to_prev"], axis=-1)
    if g["V"].shape[1] == 3:
        g["cross"] = np.linalg.norm(np.cross(g["to_next"], g["to_prev"]), axis=-1)
    else:
        g["cross"] = np.abs(g["to_next"][..., 0] * g["to_prev"][..., 1] - g["to_next"][..., 1] * g["to_prev"][..., 0])
    return g


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
    g = _geometry(V, F)
    return 0.5 * g["dot"] / g["cross"]
''',
    'cotangent_laplacian': r'''import numpy as np
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
    n = np.shape(V)[0]
    g = _geometry(V, F)
    e = {"i": g["F"][:, [1, 2, 0]].ravel(), "j": g["F"][:, [2, 0, 1]].ravel(),
         "c": cotangent_weights(V, F).ravel()}
    W = sp.csr_matrix((e["c"], (e["i"], e["j"])), shape=(n, n))
    W = (W + W.T).tolil()
    W.setdiag(-np.asarray(W.sum(axis=1)).ravel())
    return W.tocsr()
''',
    'arap_covariances': r'''import numpy as np


def _edges(V, U, F):
    F = np.asarray(F, dtype=np.int64)
    e = {"tail": F[:, [1, 2, 0]], "head": F[:, [2, 0, 1]]}
    e["rest"] = np.asarray(V, dtype=float)[e["head"]] - np.asarray(V, dtype=float)[e["tail"]]
    e["def"] = np.asarray(U, dtype=float)[e["head"]] - np.asarray(U, dtype=float)[e["tail"]]
    return e


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
    e = _edges(V, U, F)
    F = np.asarray(F, dtype=np.int64)
    n, d = np.shape(V)
    per_triangle = np.einsum("tk,tka,tkb->tab", np.asarray(C, dtype=float), e["rest"], e["def"])
    S = np.zeros((n, d, d))
    owners = F.ravel()
    for a in range(d):
        for b in range(d):
            S[:, a, b] = np.bincount(owners, weights=np.repeat(per_triangle[:, a, b], 3), minlength=n)
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
    e = _edges(V, U, F)
    F = np.asarray(F, dtype=np.int64)
    R_corners = np.asarray(R, dtype=float)[F]                       # (f, 3, d, d)
    rotated = np.matmul(R_corners[:, :, None], e["rest"][:, None, :, :, None])[..., 0]   # (f, corner, edge, d)
    diff = e["def"][:, None] - rotated
    return float(np.sum(np.asarray(C, dtype=float)[:, None, :] * np.sum(diff ** 2, axis=-1)))
''',
}
LOSES = set()
