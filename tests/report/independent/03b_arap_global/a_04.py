import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
from scipy.sparse.linalg import factorized


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
    V = np.asarray(V, float)
    F = np.asarray(F)
    h = np.asarray(handles).astype(np.int64)
    n = len(V)
    if h.size == 0:
        raise ValueError("need at least one handle")
    if np.unique(h).size != h.size:
        raise ValueError("handles must be distinct")
    if (h < 0).any() or (h >= n).any():
        raise ValueError("handle index out of range")
    free = np.setdiff1d(np.arange(n), h)
    C = cotangent_weights(V, F)
    A = -cotangent_laplacian(V, F).tocsc()
    return dict(V=V, F=F, C=C, h=h, free=free, Afh=A[free][:, h],
                solve=factorized(A[free][:, free].tocsc()))
''',
    'arap_global_step': r'''import numpy as np


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
    V, F, C = data["V"], data["F"], data["C"]
    n, d = V.shape
    Rbar = np.einsum("tcij->tij", np.asarray(R, float)[F]) / 3.0
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    y = np.einsum("tk,tij,tkj->tki", C, Rbar, e)
    B = np.zeros((n, d))
    np.add.at(B, F[:, [2, 0, 1]].ravel(), y.reshape(-1, d))
    np.add.at(B, F[:, [1, 2, 0]].ravel(), -y.reshape(-1, d))
    Uh = np.asarray(handle_positions, float)
    rhs = B[data["free"]] - data["Afh"] @ Uh
    U = np.empty((n, d))
    U[data["h"]] = Uh
    U[data["free"]] = np.column_stack([data["solve"](rhs[:, i]) for i in range(d)])
    return U
''',
    'arap_solve': r'''import numpy as np


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
    U = np.array(data["V"] if U0 is None else U0, float)
    U[data["h"]] = handle_positions
    E = []
    for _ in range(iterations):
        R = arap_rotations(data["V"], U, data["F"], data["C"])
        U = arap_global_step(data, R, handle_positions)
        E.append(arap_energy(data["V"], U, data["F"], data["C"], R))
    return U, np.asarray(E)
''',
    'laplacian_editing': r'''import numpy as np


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
    d = np.shape(V)[1]
    return arap_global_step(arap_precompute(V, F, handles), np.einsum("n,ij->nij", np.ones(len(V)), np.eye(d)),
                            handle_positions)
''',
}
LOSES = set()
