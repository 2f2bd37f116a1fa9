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
    V = np.array(V, dtype=float)
    n = len(V)
    handles = np.array(handles, dtype=int)
    if len(handles) == 0:
        raise ValueError("no handles")
    if len(set(handles.tolist())) != len(handles):
        raise ValueError("repeated handle")
    for h in handles:
        if h < 0 or h >= n:
            raise ValueError("handle out of range: " + str(h))
    hs = set(handles.tolist())
    free = np.array([i for i in range(n) if i not in hs], dtype=int)
    C = cotangent_weights(V, F)
    A = (-cotangent_laplacian(V, F)).tocsc()
    Aff = A[free, :][:, free]
    Afh = A[free, :][:, handles]
    data = {"V": V, "F": np.array(F), "C": C, "handles": handles, "free": free,
            "Afh": Afh, "solve": factorized(Aff.tocsc())}
    return data
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
    V = data["V"]
    F = data["F"]
    C = data["C"]
    n, d = V.shape
    hp = np.array(handle_positions, dtype=float)
    B = np.zeros((n, d))
    for t in range(len(F)):
        Rm = (R[F[t][0]] + R[F[t][1]] + R[F[t][2]]) / 3
        for k in range(3):
            a = F[t][(k + 1) % 3]
            b = F[t][(k + 2) % 3]
            v = C[t][k] * (Rm @ (V[a] - V[b]))
            B[a] += v
            B[b] -= v
    rhs = B[data["free"]] - data["Afh"] @ hp
    U = np.zeros((n, d))
    U[data["handles"]] = hp
    for c in range(d):
        U[data["free"], c] = data["solve"](rhs[:, c])
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
    if U0 is None:
        U = data["V"].copy()
    else:
        U = np.array(U0, dtype=float)
    U[data["handles"]] = handle_positions
    energies = []
    for it in range(iterations):
        R = arap_rotations(data["V"], U, data["F"], data["C"])
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(data["V"], U, data["F"], data["C"], R))
    return U, energies
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
    R = np.array([np.eye(d) for i in range(n)])
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
