import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
from scipy.sparse.linalg import splu


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
    n = len(V)
    fixed = np.asarray(handles, dtype=np.int64)
    if fixed.size == 0:
        raise ValueError("handles: at least one vertex has to be pinned")
    if np.unique(fixed).size < fixed.size:
        raise ValueError("handles: a vertex is pinned twice")
    if fixed.min() < 0 or fixed.max() > n - 1:
        raise ValueError("handles: index outside the mesh")
    mask = np.ones(n, dtype=bool)
    mask[fixed] = False
    free = np.nonzero(mask)[0]
    C = cotangent_weights(V, F)
    stiffness = (-cotangent_laplacian(V, F)).tocsc()
    tail, head, face = _half_edges(F)
    return {
        "V": V, "F": F, "C": C, "fixed": fixed, "free": free,
        "tail": tail, "head": head, "face": face,
        "rest_edges": V[head] - V[tail],
        "coupling": stiffness[free][:, fixed],
        "lu": splu(stiffness[free][:, free].tocsc()),
    }
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
    R = np.asarray(R, dtype=float)
    target = np.asarray(handle_positions, dtype=float)
    V, F = data["V"], data["F"]
    n, d = V.shape
    # mean rotation of each face, then each half-edge pulls with c * Rbar e
    R_face = R[F].sum(axis=1) / 3.0
    pull = data["C"].ravel()[:, None] * np.einsum("hij,hj->hi", R_face[data["face"]], data["rest_edges"])
    B = np.zeros((n, d))
    np.add.at(B, data["head"], pull)
    np.add.at(B, data["tail"], -pull)
    U = np.zeros((n, d))
    U[data["fixed"]] = target
    U[data["free"]] = data["lu"].solve(B[data["free"]] - data["coupling"] @ target)
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
    V, F, C = data["V"], data["F"], data["C"]
    U = V.copy() if U0 is None else np.asarray(U0, dtype=float).copy()
    U[data["fixed"]] = np.asarray(handle_positions, dtype=float)
    history = []
    for step in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        history.append(arap_energy(V, U, F, C, R))
    return U, np.array(history)
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
    data = arap_precompute(V, F, handles)
    n, d = data["V"].shape
    R = np.repeat(np.eye(d)[None, :, :], n, axis=0)
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
