import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = "03b_arap_global"
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
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
