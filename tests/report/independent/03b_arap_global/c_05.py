import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = "03b_arap_global"
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    "arap_precompute": r'''import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _as_int(x):
    return np.asarray(x, dtype=np.int64)


def _check_handles(handles, n):
    if handles.size == 0:
        raise ValueError("handles is empty")
    if np.unique(handles).size != handles.size:
        raise ValueError("handles repeats a vertex")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError("handle out of range")


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
    V, F = _as_float(V), _as_int(F)
    handles = _as_int(handles).reshape(-1)
    n = V.shape[0]
    _check_handles(handles, n)
    free = np.setdiff1d(np.arange(n), handles)
    C = cotangent_weights(V, F)
    L = sp.csr_matrix(cotangent_laplacian(V, F))
    A = sp.csc_matrix(-L[free, :][:, free])
    return types.SimpleNamespace(
        V=V, F=F, C=C, L=L, handles=handles, free=free,
        L_fh=L[free, :][:, handles], solve=spla.factorized(A),
    )
''',
    "arap_global_step": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


def _opposite_edges(X, F):
    return X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]


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
    R = _as_float(R)
    Uh = _as_float(handle_positions)
    V, F, C = data.V, data.F, data.C
    Rt = (R[F[:, 0]] + R[F[:, 1]] + R[F[:, 2]]) / 3.0
    # edge opposite corner k goes from a = F[:, k+1] to b = F[:, k+2]
    G = np.einsum("fk,fab,fkb->fka", C, Rt, _opposite_edges(V, F))
    B = np.zeros_like(V)
    np.add.at(B, F[:, [2, 0, 1]], G)
    np.add.at(B, F[:, [1, 2, 0]], -G)
    rhs = B[data.free] + data.L_fh @ Uh
    U = np.zeros_like(V)
    U[data.handles] = Uh
    for c in range(V.shape[1]):
        U[data.free, c] = data.solve(np.ascontiguousarray(rhs[:, c]))
    return U
''',
    "arap_solve": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


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
    Uh = _as_float(handle_positions)
    U = data.V.copy() if U0 is None else _as_float(U0).copy()
    U[data.handles] = Uh
    energies = []
    for _ in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)
        U = arap_global_step(data, R, Uh)
        energies.append(arap_energy(data.V, U, data.F, data.C, R))
    return U, np.asarray(energies)
''',
    "laplacian_editing": r'''import numpy as np


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


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
    V = _as_float(V)
    data = arap_precompute(V, F, handles)
    n, d = V.shape
    R = np.zeros((n, d, d))
    R[:, np.arange(d), np.arange(d)] = 1.0
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
