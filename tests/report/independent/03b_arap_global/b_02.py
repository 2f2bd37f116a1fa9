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
    V = np.array(V, dtype=float)
    F = np.array(F, dtype=int)
    b = np.array(handles, dtype=int).flatten()
    nv = V.shape[0]
    if len(b) < 1:
        raise ValueError('no handles given')
    if len(np.unique(b)) < len(b):
        raise ValueError('duplicate handle')
    if np.any(b < 0) or np.any(b > nv - 1):
        raise ValueError('handle out of range')
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F)
    free = np.setdiff1d(np.arange(nv), b)
    A = -L.tocsr()
    Aff = A[free, :][:, free]
    Afh = A[free, :][:, b]
    solver = spla.factorized(Aff.tocsc())
    data = {'V': V, 'F': F, 'C': C, 'L': L, 'b': b, 'free': free,
            'Afh': Afh, 'solver': solver}
    return data
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
    V = data['V']
    F = data['F']
    C = data['C']
    b = data['b']
    free = data['free']
    R = np.array(R, dtype=float)
    bc = np.array(handle_positions, dtype=float)
    nv, dim = V.shape
    Rt = (R[F[:, 0]] + R[F[:, 1]] + R[F[:, 2]]) / 3.0
    B = np.zeros((nv, dim))
    for k in range(3):
        i1 = F[:, (k + 1) % 3]
        i2 = F[:, (k + 2) % 3]
        rhs = C[:, k][:, None] * np.einsum('fij,fj->fi', Rt, V[i1, :] - V[i2, :])
        np.add.at(B, i1, rhs)
        np.add.at(B, i2, -rhs)
    Unew = np.zeros((nv, dim))
    Unew[b, :] = bc
    rhs_free = B[free, :] - data['Afh'] @ bc
    for c in range(dim):
        Unew[free, c] = data['solver'](rhs_free[:, c])
    return Unew
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
        U = data['V'].copy()
    else:
        U = np.array(U0, dtype=float)
    U[data['b'], :] = np.array(handle_positions, dtype=float)
    energies = np.zeros(iterations)
    for it in range(iterations):
        R = arap_rotations(data['V'], U, data['F'], data['C'])
        U = arap_global_step(data, R, handle_positions)
        energies[it] = arap_energy(data['V'], U, data['F'], data['C'], R)
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
    nv, dim = np.shape(V)
    data = arap_precompute(V, F, handles)
    Rid = np.zeros((nv, dim, dim))
    for i in range(nv):
        Rid[i] = np.eye(dim)
    U = arap_global_step(data, Rid, handle_positions)
    return U
''',
}
LOSES = set()
