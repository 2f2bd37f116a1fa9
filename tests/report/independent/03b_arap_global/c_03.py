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
    V = np.array(V, dtype=float)
    F = np.array(F, dtype=int)
    n = len(V)
    handles = np.array(handles, dtype=int).ravel()
    if len(handles) == 0:
        raise ValueError("no handles")
    handle_set = set(int(h) for h in handles)
    if len(handle_set) < len(handles):
        raise ValueError("repeated handle")
    for h in handle_set:
        if h < 0 or h >= n:
            raise ValueError("handle out of range")
    free = np.array(sorted(set(range(n)) - handle_set), dtype=int)
    C = cotangent_weights(V, F)
    L = sp.csr_matrix(cotangent_laplacian(V, F))
    # for every vertex a: the triangles t around it, the other end b of each of the
    # two edges (a, b) of t, and the weight of that edge in t
    spokes = {a: ([], [], []) for a in range(n)}
    for t in range(len(F)):
        for m in range(3):
            a = int(F[t, m])
            for s in (1, 2):
                b = int(F[t, (m + s) % 3])
                k = (m + 3 - s) % 3  # the corner opposite the edge (a, b)
                spokes[a][0].append(t)
                spokes[a][1].append(b)
                spokes[a][2].append(C[t, k])
    spokes = {a: (np.array(ts, dtype=int), np.array(bs, dtype=int), np.array(cs)) for a, (ts, bs, cs) in spokes.items()}
    A = -L[free][:, free]
    data = {
        "V": V, "F": F, "C": C, "L": L, "n": n,
        "handles": handles, "free": free, "spokes": spokes,
        "L_fh": L[free][:, handles],
        "solver": spla.factorized(sp.csc_matrix(A)),
    }
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
    V = data["V"]
    F = data["F"]
    R = np.array(R, dtype=float)
    handle_positions = np.array(handle_positions, dtype=float)
    Rbar = (R[F[:, 0]] + R[F[:, 1]] + R[F[:, 2]]) / 3.0
    B = np.zeros(V.shape)
    for a in range(data["n"]):
        ts, bs, cs = data["spokes"][a]
        B[a] = np.einsum("t,tij,tj->i", cs, Rbar[ts], V[a] - V[bs])
    free = data["free"]
    rhs = B[free] + data["L_fh"].dot(handle_positions)
    U = np.zeros(V.shape)
    U[data["handles"]] = handle_positions
    for c in range(V.shape[1]):
        U[free, c] = data["solver"](rhs[:, c])
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
        U = V.copy()
    else:
        U = np.array(U0, dtype=float)
    U[data["handles"]] = handle_positions
    energies = []
    for it in range(iterations):
        R = arap_rotations(V, U, data["F"], data["C"])
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(V, U, data["F"], data["C"], R))
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
    R = np.array([np.eye(d)] * n)
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
