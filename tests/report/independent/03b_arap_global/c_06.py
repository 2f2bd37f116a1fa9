import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = "03b_arap_global"
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    "arap_precompute": r'''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


class ArapData:
    pass


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
    data = ArapData()
    data.V = np.asarray(V, dtype=float)
    data.F = np.asarray(F, dtype=np.int64)
    h = np.asarray(handles, dtype=np.int64).ravel()
    n = data.V.shape[0]
    if h.size < 1:
        raise ValueError("need at least one handle")
    if np.any((h < 0) | (h >= n)):
        raise ValueError("handle index out of range")
    if np.unique(h).size < h.size:
        raise ValueError("duplicate handles")
    data.handles = h
    mask = np.ones(n, dtype=bool)
    mask[h] = False
    data.free = np.nonzero(mask)[0]
    data.C = cotangent_weights(data.V, data.F)
    data.L = sp.csc_matrix(cotangent_laplacian(data.V, data.F))
    K = -data.L
    data.K_fh = K[data.free, :][:, h]
    data.lu = spla.splu(sp.csc_matrix(K[data.free, :][:, data.free]))
    return data
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
    Rot = np.asarray(R, dtype=float)
    Uh = np.asarray(handle_positions, dtype=float)
    X, T, W = data.V, data.F, data.C
    Rm = (Rot[T[:, 0]] + Rot[T[:, 1]] + Rot[T[:, 2]]) / 3.0
    B = np.zeros(X.shape)
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        r = W[:, k][:, None] * np.einsum("tab,tb->ta", Rm, X[i] - X[j])
        np.add.at(B, i, r)
        np.add.at(B, j, -r)
    rhs = B[data.free] - data.K_fh @ Uh
    out = np.empty(X.shape)
    out[data.handles] = Uh
    out[data.free] = data.lu.solve(rhs)
    return out
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
    Uh = np.asarray(handle_positions, dtype=float)
    cur = np.array(data.V if U0 is None else U0, dtype=float, copy=True)
    cur[data.handles] = Uh
    energies = np.empty(iterations)
    for k in range(iterations):
        Rot = arap_rotations(data.V, cur, data.F, data.C)
        cur = arap_global_step(data, Rot, Uh)
        energies[k] = arap_energy(data.V, cur, data.F, data.C, Rot)
    return cur, energies
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
    Rot = np.repeat(np.eye(d)[None], n, axis=0)
    return arap_global_step(data, Rot, handle_positions)
''',
}
LOSES = set()
