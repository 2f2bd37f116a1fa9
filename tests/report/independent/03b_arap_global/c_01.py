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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F, dtype=int)
    h = np.asarray(handles, dtype=int).ravel()
    n = len(V)
    hs = set(h.tolist())
    if len(h) == 0 or len(hs) != len(h) or any(i < 0 or i >= n for i in hs):
        raise ValueError("handles must be distinct vertex indices, at least one")
    free = np.array([i for i in range(n) if i not in hs], dtype=int)
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    Lf = L[free]
    return {
        "V": V, "F": F, "C": C, "L": L, "handles": h, "free": free,
        "L_fh": Lf[:, h], "solve": spla.factorized((-Lf[:, free]).tocsc()),
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
    hp = np.asarray(handle_positions, dtype=float)
    Rbar = sum(R[F[:, i]] for i in range(3)) / 3.0
    B = np.zeros_like(V)
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        g = C[:, k, None] * np.einsum("tij,tj->ti", Rbar, V[a] - V[b])
        np.add.at(B, a, g)
        np.add.at(B, b, -g)
    rhs = B[data["free"]] + data["L_fh"] @ hp
    U = np.empty_like(V)
    U[data["handles"]] = hp
    U[data["free"]] = np.column_stack([data["solve"](col) for col in rhs.T])
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
    U = np.array(V if U0 is None else U0, dtype=float)
    U[data["handles"]] = handle_positions
    energies = []
    for _ in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(V, U, F, C, R))
    return U, np.array(energies)
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
    identities = np.array([np.eye(d) for _ in range(n)])
    return arap_global_step(data, identities, handle_positions)
''',
}
LOSES = set()
