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
    pts = np.asarray(V, dtype=float)
    tri = np.asarray(F)
    fixed = np.asarray(handles, dtype=np.int64)
    nv = len(pts)
    if fixed.ndim != 1 or len(fixed) == 0:
        raise ValueError("handles must be a non-empty 1-D index array")
    if np.any((fixed < 0) | (fixed >= nv)):
        raise ValueError("handle index out of range")
    if len(np.unique(fixed)) != len(fixed):
        raise ValueError("duplicate handle index")
    cot = cotangent_weights(pts, tri)
    L = cotangent_laplacian(pts, tri)
    free = np.ones(nv, dtype=bool)
    free[fixed] = False
    free = np.nonzero(free)[0]
    stiff = (-L).tocsc()
    lu = spla.splu(stiff[free, :][:, free])
    return {"V": pts, "F": tri, "C": cot, "L": L, "fixed": fixed, "free": free,
            "coupling": stiff[free, :][:, fixed], "lu": lu}
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
    pts, tri, cot = data["V"], data["F"], data["C"]
    rot = np.asarray(R, dtype=float)
    target = np.asarray(handle_positions, dtype=float)
    nv, dim = pts.shape
    mean_rot = (rot[tri[:, 0]] + rot[tri[:, 1]] + rot[tri[:, 2]]) / 3.0
    rhs = np.zeros((nv, dim))
    for k in range(3):
        i = tri[:, (k + 1) % 3]
        j = tri[:, (k + 2) % 3]
        contrib = cot[:, k, None] * np.einsum("tab,tb->ta", mean_rot, pts[i] - pts[j])
        np.add.at(rhs, i, contrib)
        np.add.at(rhs, j, -contrib)
    result = np.zeros((nv, dim))
    result[data["fixed"]] = target
    result[data["free"]] = data["lu"].solve(rhs[data["free"]] - data["coupling"] @ target)
    return result
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
    pts = data["V"]
    cur = pts.copy() if U0 is None else np.array(U0, dtype=float, copy=True)
    cur[data["fixed"]] = handle_positions
    history = []
    for _ in range(iterations):
        rot = arap_rotations(pts, cur, data["F"], data["C"])
        cur = arap_global_step(data, rot, handle_positions)
        history.append(arap_energy(pts, cur, data["F"], data["C"], rot))
    return cur, np.array(history)
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
    pts = np.asarray(V, dtype=float)
    dim = pts.shape[1]
    identity = np.zeros((len(pts), dim, dim))
    identity[:, np.arange(dim), np.arange(dim)] = 1.0
    return arap_global_step(arap_precompute(pts, F, handles), identity, handle_positions)
''',
}
LOSES = set()
