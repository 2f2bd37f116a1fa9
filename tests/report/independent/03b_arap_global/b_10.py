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
