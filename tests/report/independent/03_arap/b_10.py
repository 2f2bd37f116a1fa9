NOTEBOOK = "03_arap"
DESCRIPTION = "reuse-everything student: energy from three arap_covariances calls (trace identity), Laplacian from weights, solve/editing only call earlier functions; rank-one reflection fix"
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
    S = np.asarray(S, dtype=float)
    u, _, vt = np.linalg.svd(S)
    R = np.swapaxes(vt, -1, -2) @ np.swapaxes(u, -1, -2)
    # a reflection: subtract twice the last singular pair, R - 2 v_d u_d^T
    neg = (np.linalg.det(R) < 0).astype(float)
    v_last = vt[..., -1, :]
    u_last = u[..., :, -1]
    fix = v_last[..., :, None] * u_last[..., None, :]
    return R - 2.0 * neg[..., None, None] * fix
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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    corners = V[F]
    to_next = corners[:, [1, 2, 0]] - corners
    to_prev = corners[:, [2, 0, 1]] - corners
    dot = np.einsum("tkd,tkd->tk", to_next, to_prev)
    if V.shape[1] == 2:
        cross = to_next[..., 0] * to_prev[..., 1] - to_next[..., 1] * to_prev[..., 0]
    else:
        cross = np.linalg.norm(np.cross(to_next, to_prev), axis=-1)
    return dot / np.abs(cross) / 2
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
    F = np.asarray(F)
    n = len(V)
    C = cotangent_weights(V, F)
    a = F[:, [1, 2, 0]].ravel()
    b = F[:, [2, 0, 1]].ravel()
    c = C.ravel()
    rows = np.concatenate([a, b, a, b])
    cols = np.concatenate([b, a, a, b])
    vals = np.concatenate([c, c, -c, -c])
    return sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F)
    n, d = V.shape
    a = F[:, [1, 2, 0]]
    b = F[:, [2, 0, 1]]
    per_tri = np.einsum("tk,tki,tkj->tij", np.asarray(C, dtype=float), V[b] - V[a], U[b] - U[a])
    S = np.zeros((n, d, d))
    np.add.at(S, F.ravel(), np.repeat(per_tri, 3, axis=0))
    return S
''',
    "arap_rotations": '''def arap_rotations(V, U, F, C):
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
    # |e' - R e|^2 = e'.e' - 2 tr(R e e'^T) + tr(R e e^T R^T), summed over each cell:
    # all three sums are covariance stacks
    R = np.asarray(R, dtype=float)
    S_vu = arap_covariances(V, U, F, C)
    S_uu = arap_covariances(U, U, F, C)
    S_vv = arap_covariances(V, V, F, C)
    E = (np.trace(S_uu, axis1=1, axis2=2).sum()
         - 2.0 * np.einsum("nij,nji->", R, S_vu)
         + np.einsum("nij,njk,nik->", R, S_vv, R))
    return float(E)
''',
    "arap_precompute": '''import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def arap_precompute(V, F, handles):
    """What the ARAP iterations reuse: the rest mesh, the weights and the factorized system.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
        Triangles.
    handles : (h,) array_like of int
        Distinct vertex indices whose positions are prescribed; at least one.

    Returns
    -------
    data : object of your design
        Everything ``arap_global_step`` and ``arap_solve`` need.

    Raises
    ------
    ValueError
        If ``handles`` is empty, repeats a vertex or is out of range.
    """
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    handles = np.asarray(handles, dtype=np.int64)
    n = len(V)
    if handles.size == 0 or handles.min() < 0 or handles.max() >= n or len(set(handles.tolist())) < handles.size:
        raise ValueError("handles must be non-empty, distinct and in range")
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F)
    free = np.delete(np.arange(n), handles)
    L_ff = L[free][:, free]
    return types.SimpleNamespace(V=V, F=F, C=C, L=L, handles=handles, free=free,
                                 L_fh=L[free][:, handles],
                                 solve=spla.factorized(sp.csc_matrix(-L_ff)))
''',
    "arap_global_step": '''import numpy as np


def arap_global_step(data, R, handle_positions):
    """The global step: the positions minimizing the ARAP energy for fixed rotations.

    Parameters
    ----------
    data : object
        From ``arap_precompute``.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.
    handle_positions : (h, d) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, d) numpy.ndarray
        ``U[handles] = handle_positions``; the free rows solve ``(-L)_ff U_f = B_f - (-L)_fh U_h``.
    """
    V, F, C = data.V, data.F, data.C
    R_bar = np.asarray(R, dtype=float)[F].mean(axis=1)
    a = F[:, [1, 2, 0]]
    b = F[:, [2, 0, 1]]
    pull = np.einsum("tk,tij,tkj->tki", C, R_bar, V[a] - V[b])
    B = np.zeros_like(V)
    np.add.at(B, a.ravel(), pull.reshape(-1, V.shape[1]))
    np.add.at(B, b.ravel(), -pull.reshape(-1, V.shape[1]))
    U = V.copy()
    U[data.handles] = handle_positions
    rhs = B[data.free] + data.L_fh @ U[data.handles]
    U[data.free] = np.column_stack([data.solve(col) for col in rhs.T])
    return U
''',
    "arap_solve": '''import numpy as np


def arap_solve(data, handle_positions, U0=None, iterations=10):
    """ARAP deformation: alternate the local and the global step.

    Parameters
    ----------
    data : object
        From ``arap_precompute``.
    handle_positions : (h, d) array_like of float
        Where the handles go.
    U0 : (n, d) array_like of float, optional
        The start; the rest positions by default. Its handle rows are replaced by
        ``handle_positions`` first.
    iterations : int
        Local–global iterations.

    Returns
    -------
    U : (n, d) numpy.ndarray
        The positions after the last iteration.
    energies : (iterations,) numpy.ndarray
        ``energies[k]``: the energy after iteration ``k``'s global step, with the rotations it used.
    """
    U = np.array(data.V if U0 is None else U0, dtype=float)
    U[data.handles] = handle_positions
    energies = []
    while len(energies) < iterations:
        R = arap_rotations(data.V, U, data.F, data.C)
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(data.V, U, data.F, data.C, R))
    return U, np.array(energies)
''',
    "laplacian_editing": '''import numpy as np


def laplacian_editing(V, F, handles, handle_positions):
    """Naive Laplacian editing: the global step with every rotation the identity.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
        Triangles.
    handles : (h,) array_like of int
        Vertex indices.
    handle_positions : (h, d) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, d) numpy.ndarray
    """
    data = arap_precompute(V, F, handles)
    d = data.V.shape[1]
    identities = np.repeat(np.eye(d)[np.newaxis], len(data.V), axis=0)
    return arap_global_step(data, identities, handle_positions)
''',
}
LOSES = set()
