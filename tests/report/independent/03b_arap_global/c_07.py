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
    F = np.asarray(F, dtype=int)
    handles = np.asarray(handles, dtype=int)
    n = V.shape[0]
    if len(handles) == 0:
        raise ValueError("handles is empty")
    if len(np.unique(handles)) != len(handles):
        raise ValueError("handles contains a repeated vertex")
    if handles.min() < 0 or handles.max() > n - 1:
        raise ValueError("handles out of range")
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    free = np.array([i for i in range(n) if i not in set(handles.tolist())])
    Lff = L[free][:, free]
    Lfh = L[free][:, handles]
    solver = spla.factorized((-Lff).tocsc())
    return {"V": V, "F": F, "C": C, "L": L, "dim": V.shape[1],
            "handles": handles, "free": free, "Lfh": Lfh, "solver": solver}
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
    V = data["V"]
    F = data["F"]
    C = data["C"]
    R = np.asarray(R, dtype=float)
    H = np.asarray(handle_positions, dtype=float)
    Rm = (R[F[:, 0]] + R[F[:, 1]] + R[F[:, 2]]) / 3.0
    B = np.zeros(V.shape)
    for k in range(3):
        a = F[:, (k + 1) % 3]
        b = F[:, (k + 2) % 3]
        e = V[a] - V[b]
        if data["dim"] == 2:
            gx = C[:, k] * (Rm[:, 0, 0] * e[:, 0] + Rm[:, 0, 1] * e[:, 1])
            gy = C[:, k] * (Rm[:, 1, 0] * e[:, 0] + Rm[:, 1, 1] * e[:, 1])
            g = np.column_stack([gx, gy])
        else:
            g = C[:, k, None] * np.matmul(Rm, e[:, :, None])[:, :, 0]
        np.add.at(B, a, g)
        np.add.at(B, b, -g)
    free = data["free"]
    rhs = B[free] + data["Lfh"] @ H
    U = np.zeros(V.shape)
    U[data["handles"]] = H
    if data["dim"] == 2:
        U[free, 0] = data["solver"](rhs[:, 0])
        U[free, 1] = data["solver"](rhs[:, 1])
    else:
        U[free, 0] = data["solver"](rhs[:, 0])
        U[free, 1] = data["solver"](rhs[:, 1])
        U[free, 2] = data["solver"](rhs[:, 2])
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
    V = data["V"]
    if U0 is None:
        U = np.array(V, dtype=float)
    else:
        U = np.array(U0, dtype=float)
    U[data["handles"]] = np.asarray(handle_positions, dtype=float)
    energies = []
    for it in range(iterations):
        R = arap_rotations(V, U, data["F"], data["C"])
        U = arap_global_step(data, R, handle_positions)
        E = arap_energy(V, U, data["F"], data["C"], R)
        energies.append(E)
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
    n = len(data["V"])
    if data["dim"] == 2:
        R = np.tile(np.eye(2), (n, 1, 1))
    else:
        R = np.tile(np.eye(3), (n, 1, 1))
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
