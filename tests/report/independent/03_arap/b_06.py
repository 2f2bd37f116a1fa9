NOTEBOOK = "03_arap"
DESCRIPTION = "normal-equations student: builds the weighted edge-difference matrix G and solves G^T W G u = G^T W (R e) for the global step"
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
    U_s, sv, Vt_s = np.linalg.svd(S)
    Ut = np.swapaxes(U_s, -1, -2)
    V_s = np.swapaxes(Vt_s, -1, -2)
    sign = np.sign(np.linalg.det(V_s @ Ut))
    V_s = V_s.copy()
    V_s[..., :, -1] = V_s[..., :, -1] * sign[..., None]
    return V_s @ Ut
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
    out = []
    for k in range(3):
        o = V[F[:, k]]
        a = V[F[:, (k + 1) % 3]] - o
        b = V[F[:, (k + 2) % 3]] - o
        if V.shape[1] == 2:
            s = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        else:
            s = np.sqrt((np.cross(a, b) ** 2).sum(axis=1))
        out.append((a * b).sum(axis=1) / (2.0 * s))
    return np.stack(out, axis=1)
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
    F = np.asarray(F, dtype=np.int64)
    n = np.shape(V)[0]
    f = F.shape[0]
    C = cotangent_weights(V, F)
    # G: one row per (triangle, edge), +1 at one end and -1 at the other
    heads = np.concatenate([F[:, (k + 1) % 3] for k in range(3)])
    tails = np.concatenate([F[:, (k + 2) % 3] for k in range(3)])
    m = 3 * f
    rows = np.concatenate([np.arange(m), np.arange(m)])
    G = sp.csr_matrix((np.r_[np.ones(m), -np.ones(m)], (rows, np.r_[heads, tails])), shape=(m, n))
    Wd = sp.diags(np.concatenate([C[:, k] for k in range(3)]))
    # u^T (G^T W G) u = sum c |u_i - u_j|^2, and that is -L
    return (-(G.T @ Wd @ G)).tocsr()
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
    n, d = V.shape
    f = F.shape[0]
    E = np.stack([V[F[:, (k + 1) % 3]] - V[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    Ep = np.stack([U[F[:, (k + 1) % 3]] - U[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    T = np.einsum("fk,fki,fkj->fij", C, E, Ep).reshape(f, d * d)
    # vertex-triangle incidence matrix, (n, f)
    A = sp.coo_matrix((np.ones(3 * f), (F.T.ravel(), np.tile(np.arange(f), 3))), shape=(n, f)).tocsr()
    return (A @ T).reshape(n, d, d)
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
    S = arap_covariances(V, U, F, C)
    R = optimal_rotation(S)
    return R
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
    E = np.stack([V[F[:, (k + 1) % 3]] - V[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    Ep = np.stack([U[F[:, (k + 1) % 3]] - U[F[:, (k + 2) % 3]] for k in range(3)], axis=1)
    total = 0.0
    for c in range(3):
        RE = np.einsum("fij,fkj->fki", R[F[:, c]], E)
        total += np.einsum("fk,fki,fki->", C, Ep - RE, Ep - RE)
    return float(total)
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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    hnd = np.asarray(handles, dtype=np.int64).ravel()
    n = V.shape[0]
    if hnd.size == 0:
        raise ValueError("handles is empty")
    if np.unique(hnd).size != hnd.size:
        raise ValueError("handles repeats a vertex")
    if hnd.min() < 0 or hnd.max() >= n:
        raise ValueError("handles out of range")
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F)
    f = F.shape[0]
    m = 3 * f
    heads = np.concatenate([F[:, (k + 1) % 3] for k in range(3)])
    tails = np.concatenate([F[:, (k + 2) % 3] for k in range(3)])
    G = sp.csr_matrix((np.r_[np.ones(m), -np.ones(m)],
                       (np.r_[np.arange(m), np.arange(m)], np.r_[heads, tails])), shape=(m, n))
    w = np.concatenate([C[:, k] for k in range(3)])
    K = (G.T @ sp.diags(w) @ G).tocsc()          # normal-equation matrix = -L
    free = np.setdiff1d(np.arange(n), hnd)
    K_ff = K[free][:, free]
    K_fh = K[free][:, hnd]
    ns = types.SimpleNamespace(V=V, F=F, C=C, L=L, G=G, w=w, handles=hnd, free=free,
                               K_fh=K_fh.tocsr(), solve=spla.factorized(K_ff.tocsc()))
    return ns
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
    V, F = data.V, data.F
    n, d = V.shape
    R = np.asarray(R, dtype=np.float64)
    Uh = np.asarray(handle_positions, dtype=np.float64)
    Rbar = R[F].mean(axis=1)
    # target edge vectors R_t e for every row of G, in the same (k, t) order
    e = np.concatenate([V[F[:, (k + 1) % 3]] - V[F[:, (k + 2) % 3]] for k in range(3)])
    target = np.einsum("mij,mj->mi", np.tile(Rbar, (3, 1, 1)), e)
    # normal equations of min sum w |G u - target|^2
    B = data.G.T @ (data.w[:, None] * target)
    rhs = B[data.free] - data.K_fh @ Uh
    U = np.zeros((n, d))
    U[data.handles] = Uh
    U[data.free] = np.column_stack([data.solve(rhs[:, c]) for c in range(d)])
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
    U = np.array(data.V if U0 is None else U0, dtype=np.float64)
    U[data.handles] = np.asarray(handle_positions, dtype=np.float64)
    energies = np.empty(iterations)
    for k in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)
        U = arap_global_step(data, R, handle_positions)
        energies[k] = arap_energy(data.V, U, data.F, data.C, R)
    return U, energies
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
    n, d = data.V.shape
    return arap_global_step(data, np.tile(np.eye(d), (n, 1, 1)), handle_positions)
''',
}
LOSES = set()
