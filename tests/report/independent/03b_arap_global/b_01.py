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
    F = np.asarray(F, dtype=np.int64)
    handles = np.asarray(handles, dtype=np.int64).ravel()
    n = len(V)
    if handles.size == 0:
        raise ValueError("need at least one handle")
    if len(np.unique(handles)) != len(handles):
        raise ValueError("handles repeat a vertex")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError("handle index out of range")
    w = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    is_handle = np.zeros(n, dtype=bool)
    is_handle[handles] = True
    free = np.flatnonzero(~is_handle)
    A = (-L)[free][:, free].tocsc()
    solve = spla.splu(A) if len(free) else None
    return types.SimpleNamespace(V=V, F=F, C=w, L=L, handles=handles, free=free,
                                 L_fh=L[free][:, handles], lu=solve)
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
    V, F, w = data.V, data.F, data.C
    R = np.asarray(R, dtype=float)
    U_h = np.asarray(handle_positions, dtype=float).reshape(len(data.handles), -1)
    n, d = V.shape
    # only the triangle's mean rotation matters
    R_T = R[F].mean(axis=1)                     # (f, d, d)
    b = np.zeros((n, d))
    for k in range(3):
        i = F[:, (k + 1) % 3]
        j = F[:, (k + 2) % 3]
        e_ij = V[i] - V[j]
        r = w[:, k, None] * np.einsum("tab,tb->ta", R_T, e_ij)
        # b_i += w_ij R e_ij, b_j -= w_ij R e_ij
        np.add.at(b, i, r)
        np.add.at(b, j, -r)
    U = np.zeros((n, d))
    U[data.handles] = U_h
    if len(data.free):
        rhs = b[data.free] + data.L_fh @ U_h
        U[data.free] = data.lu.solve(rhs)
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
    if U0 is None:
        U = data.V.copy()
    else:
        U = np.array(U0, dtype=float)
    U[data.handles] = handle_positions
    energies = []
    for it in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)      # local step
        U = arap_global_step(data, R, handle_positions)     # global step
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
    d = np.shape(V)[1]
    R = np.tile(np.eye(d), (len(data.V), 1, 1))
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
