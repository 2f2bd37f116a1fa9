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
    pts = np.array(V, dtype=np.float64)
    tris = np.array(F, dtype=np.int64)
    fixed = np.array(handles, dtype=np.int64).flatten()
    n = len(pts)
    if len(fixed) == 0:
        raise ValueError("at least one handle needed")
    if len(set(fixed.tolist())) != len(fixed):
        raise ValueError("handles must be distinct")
    if fixed.min() < 0 or fixed.max() >= n:
        raise ValueError("handle index out of range")
    free = np.setdiff1d(np.arange(n), fixed)
    half_cot = cotangent_weights(pts, tris)
    L = sp.csr_matrix(cotangent_laplacian(pts, tris))
    stiffness = -L
    A_ff = stiffness[free, :][:, free]
    A_fh = stiffness[free, :][:, fixed]
    return dict(V=pts, F=tris, C=half_cot, L=L, handles=fixed, free=free,
                A_fh=A_fh, factor=spla.factorized(sp.csc_matrix(A_ff)))
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
    pts, tris, half_cot = data["V"], data["F"], data["C"]
    rots = np.array(R, dtype=np.float64)
    fixed_pos = np.array(handle_positions, dtype=np.float64)
    mean_rot = (rots[tris[:, 0]] + rots[tris[:, 1]] + rots[tris[:, 2]]) / 3.0
    n, d = pts.shape
    B = np.zeros((n, d))
    for k in range(3):
        i = tris[:, (k + 1) % 3]
        j = tris[:, (k + 2) % 3]
        rotated = np.matmul(mean_rot, (pts[i] - pts[j])[:, :, None])[:, :, 0]
        rotated = half_cot[:, k].reshape(-1, 1) * rotated
        for c in range(d):
            B[:, c] += np.bincount(i, weights=rotated[:, c], minlength=n)
            B[:, c] -= np.bincount(j, weights=rotated[:, c], minlength=n)
    free = data["free"]
    rhs = B[free] - data["A_fh"] @ fixed_pos
    result = np.zeros((n, d))
    result[data["handles"]] = fixed_pos
    for c in range(d):
        result[free, c] = data["factor"](rhs[:, c])
    return result
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
    pts = data["V"]
    fixed_pos = np.array(handle_positions, dtype=np.float64)
    if U0 is None:
        current = pts.copy()
    else:
        current = np.array(U0, dtype=np.float64)
    current[data["handles"]] = fixed_pos
    energies = np.zeros(iterations)
    for it in range(iterations):
        rots = arap_rotations(pts, current, data["F"], data["C"])
        current = arap_global_step(data, rots, fixed_pos)
        energies[it] = arap_energy(pts, current, data["F"], data["C"], rots)
    return current, energies
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
    n, d = data["V"].shape
    rots = np.zeros((n, d, d))
    for c in range(d):
        rots[:, c, c] = 1.0
    return arap_global_step(data, rots, handle_positions)
''',
}
LOSES = set()
