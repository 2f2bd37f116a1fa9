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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F, dtype=np.int64)
    handles = np.atleast_1d(np.asarray(handles, dtype=np.int64))
    n = V.shape[0]
    if handles.size == 0:
        raise ValueError("empty handles")
    if any(h < 0 or h >= n for h in handles):
        raise ValueError("handle out of range")
    if len(set(handles.tolist())) != handles.size:
        raise ValueError("repeated handle")
    free = np.array(sorted(set(range(n)).difference(handles.tolist())), dtype=np.int64)
    C = cotangent_weights(V, F)
    L = sp.csr_matrix(cotangent_laplacian(V, F))
    negL_free = (-L)[free]
    return {
        "V": V,
        "F": F,
        "C": C,
        "L": L,
        "handles": handles,
        "free": free,
        "coupling": negL_free[:, handles],
        "solve": spla.factorized(sp.csc_matrix(negL_free[:, free])),
    }
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
    V, F, C = data["V"], data["F"], data["C"]
    R = np.asarray(R, dtype=float)
    Uh = np.asarray(handle_positions, dtype=float)
    Rbar = sum(R[F[:, i]] for i in range(3)) / 3.0
    B = np.zeros_like(V)
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        term = C[:, k, None] * np.einsum("tab,tb->ta", Rbar, V[a] - V[b])
        np.add.at(B, a, term)
        np.subtract.at(B, b, term)
    rhs = B[data["free"]] - data["coupling"] @ Uh
    U = np.zeros_like(V)
    U[data["handles"]] = Uh
    U[data["free"]] = np.stack(tuple(data["solve"](rhs[:, c]) for c in range(V.shape[1])), axis=1)
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
    V, F, C = data["V"], data["F"], data["C"]
    U = np.array(V, dtype=float) if U0 is None else np.array(U0, dtype=float)
    U[data["handles"]] = handle_positions
    energies = np.empty(iterations)
    for k in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        energies[k] = arap_energy(V, U, F, C, R)
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
    d = data["V"].shape[1]
    identity = np.broadcast_to(np.eye(d), (len(data["V"]), d, d))
    return arap_global_step(data, identity, handle_positions)
''',
}
LOSES = set()
