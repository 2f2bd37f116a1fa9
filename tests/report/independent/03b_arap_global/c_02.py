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
    handles = np.asarray(handles, dtype=np.int64).reshape(-1)
    n = V.shape[0]
    # check the handles before doing any work
    if handles.size == 0:
        raise ValueError("at least one handle is needed")
    if np.unique(handles).size != handles.size:
        raise ValueError("a handle vertex is repeated")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError("handle index out of range")
    # free vertices = all vertices that are not handles
    is_handle = np.zeros(n, dtype=bool)
    is_handle[handles] = True
    free = np.flatnonzero(~is_handle)
    # weights and Laplacian of the rest mesh (they never change)
    C = cotangent_weights(V, F)
    L = sp.csr_matrix(cotangent_laplacian(V, F))
    # the system matrix (-L)_ff, factorized once (CSC for the sparse LU)
    K_ff = (-L[free][:, free]).tocsc()
    solve = spla.factorized(K_ff)
    # L_fh moves the known handle columns to the right-hand side
    L_fh = L[free][:, handles]
    return types.SimpleNamespace(V=V, F=F, C=C, L=L, handles=handles, free=free, solve=solve, L_fh=L_fh)
''',
    "arap_global_step": r'''import numpy as np


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
    R = np.asarray(R, dtype=np.float64)
    U_h = np.asarray(handle_positions, dtype=np.float64)
    # only the mean rotation of each triangle matters, (f, d, d)
    R_mean = R[F].mean(axis=1)
    # edge opposite corner k: a = F[:, k+1], b = F[:, k+2], rest vector v_b - v_a
    a_idx = np.roll(F, -1, axis=1)
    b_idx = np.roll(F, -2, axis=1)
    rest_edges = V[b_idx] - V[a_idx]
    # c_ab R_t (v_a - v_b), (f, 3, d); vertex a gets +, vertex b gets -
    contrib = np.einsum("tk,tab,tkb->tka", C, R_mean, -rest_edges)
    d = V.shape[1]
    # scatter-add into B with one index array for both endpoints
    targets = np.concatenate([a_idx.ravel(), b_idx.ravel()])
    values = np.concatenate([contrib.reshape(-1, d), -contrib.reshape(-1, d)])
    B = np.zeros_like(V)
    np.add.at(B, targets, values)
    # (-L)_ff U_f = B_f + L_fh U_h, the same matrix for every coordinate column
    rhs = B[data.free] + data.L_fh @ U_h
    U = np.zeros_like(V)
    U[data.handles] = U_h
    U[data.free] = np.stack([data.solve(rhs[:, c]) for c in range(d)], axis=1)
    return U
''',
    "arap_solve": r'''import numpy as np


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
    handle_positions = np.asarray(handle_positions, dtype=np.float64)
    # start: rest pose (or U0), with the handles already where they belong
    if U0 is None:
        U = data.V.copy()
    else:
        U = np.array(U0, dtype=np.float64)
    U[data.handles] = handle_positions
    energies = np.zeros(iterations)
    for it in range(iterations):
        # local step: rotations fitted to the current positions
        R = arap_rotations(data.V, U, data.F, data.C)
        # global step: positions for these rotations
        U = arap_global_step(data, R, handle_positions)
        # energy with the rotations the global step used
        energies[it] = arap_energy(data.V, U, data.F, data.C, R)
    return U, energies
''',
    "laplacian_editing": r'''import numpy as np


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
    # every rotation is the identity: a stack of n identity matrices
    R_identity = np.tile(np.eye(d), (n, 1, 1))
    return arap_global_step(data, R_identity, handle_positions)
''',
}
LOSES = set()
