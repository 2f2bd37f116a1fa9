import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = "03b_arap_global"
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    "arap_precompute": r'''import numpy as np
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
    V, h = np.asarray(V, float), np.asarray(handles, int)
    if h.size == 0 or len(set(h.tolist())) < h.size or h.min() < 0 or h.max() >= len(V):
        raise ValueError(handles)
    free = np.setdiff1d(np.arange(len(V)), h)
    L = cotangent_laplacian(V, F).tocsr()
    return V, np.asarray(F), cotangent_weights(V, F), h, free, L[free][:, h], spla.factorized(-L[free][:, free].tocsc())
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
    V, F, C, h, free, Lfh, solve = data
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    g = np.einsum("tk,tij,tkj->tki", C, np.asarray(R)[F].mean(1), e)
    B = np.zeros_like(V)
    np.add.at(B, F[:, [2, 0, 1]], g)
    np.add.at(B, F[:, [1, 2, 0]], -g)
    U = np.zeros_like(V)
    U[h] = handle_positions
    rhs = B[free] + Lfh @ U[h]
    U[free] = np.column_stack([solve(c) for c in rhs.T])
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
    V, F, C, h = data[:4]
    U = np.array(V if U0 is None else U0, float)
    U[h] = handle_positions
    E = []
    for _ in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        E.append(arap_energy(V, U, F, C, R))
    return U, np.array(E)
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
    return arap_global_step(arap_precompute(V, F, handles), np.tile(np.eye(np.shape(V)[1]), (len(V), 1, 1)), handle_positions)
''',
}
LOSES = set()
