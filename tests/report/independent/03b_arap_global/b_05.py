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
    if len(handles) == 0:
        raise ValueError("no handles")
    seen = set()
    for h in handles:
        if h < 0 or h >= n:
            raise ValueError("handle out of range")
        if h in seen:
            raise ValueError("repeated handle")
        seen.add(h)
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F)
    free = np.array([i for i in range(n) if i not in seen], dtype=np.int64)
    # position of every vertex among the free ones
    where = -np.ones(n, dtype=np.int64)
    where[free] = np.arange(len(free))
    hwhere = {}
    for a, h in enumerate(handles):
        hwhere[h] = a
    A = sp.lil_matrix((len(free), len(free)))
    Afh = sp.lil_matrix((len(free), len(handles)))
    Lcoo = L.tocoo()
    for i, j, val in zip(Lcoo.row, Lcoo.col, Lcoo.data):
        if where[i] < 0:
            continue
        if where[j] >= 0:
            A[where[i], where[j]] -= val
        else:
            Afh[where[i], hwhere[j]] -= val
    data = types.SimpleNamespace()
    data.V = V
    data.F = F
    data.C = C
    data.L = L
    data.handles = handles
    data.free = free
    data.Afh = Afh.tocsr()
    data.lu = spla.splu(A.tocsc())
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
    V, F, C = data.V, data.F, data.C
    R = np.asarray(R, dtype=float)
    hp = np.asarray(handle_positions, dtype=float)
    n, d = V.shape
    B = np.zeros((n, d))
    for t in range(len(F)):
        Rt = (R[F[t, 0]] + R[F[t, 1]] + R[F[t, 2]]) / 3
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            v = C[t, k] * (Rt @ (V[i] - V[j]))
            B[i] += v
            B[j] -= v
    U = np.zeros((n, d))
    U[data.handles] = hp
    rhs = B[data.free] - data.Afh @ hp
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
        U = np.array(data.V, dtype=float)
    else:
        U = np.array(U0, dtype=float)
    U[data.handles] = handle_positions
    energies = []
    for k in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)
        U = arap_global_step(data, R, handle_positions)
        E = arap_energy(data.V, U, data.F, data.C, R)
        energies.append(E)
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
    R = np.zeros((n, d, d))
    for i in range(n):
        R[i] = np.identity(d)
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
