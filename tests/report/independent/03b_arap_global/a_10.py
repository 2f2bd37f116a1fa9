import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
import scipy.sparse as sp
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
    V, F = _check_mesh(V, F)
    n, d = V.shape
    handles = np.asarray(handles)
    if handles.ndim != 1:
        raise ValueError(f"handles must be a 1-D index array, got shape {handles.shape}")
    if handles.size == 0:
        raise ValueError("handles must contain at least one vertex")
    if not np.issubdtype(handles.dtype, np.integer):
        raise ValueError("handles must contain integer vertex indices")
    handles = handles.astype(np.int64)
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handles must be in [0, {n - 1}]")
    if len(np.unique(handles)) != len(handles):
        raise ValueError("handles must not contain a vertex twice")
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    is_free = np.ones(n, dtype=bool)
    is_free[handles] = False
    free = np.flatnonzero(is_free)
    A = -L
    m = 3 * len(F)
    # scatter matrix: half-edge h adds +y_h at its head and -y_h at its tail
    G = sp.csr_matrix((np.concatenate((np.ones(m), -np.ones(m))),
                       (np.concatenate((F[:, [2, 0, 1]].reshape(-1), F[:, [1, 2, 0]].reshape(-1))),
                        np.concatenate((np.arange(m), np.arange(m))))), shape=(n, m))
    solve = factorized(A[free][:, free].tocsc()) if free.size else None
    return {"V": V, "F": F, "C": C, "L": L, "handles": handles, "free": free,
            "A_fh": A[free][:, handles], "G": G, "solve": solve, "n": n, "d": d}
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
    n, d = data["n"], data["d"]
    R = np.asarray(R, dtype=float)
    if R.shape != (n, d, d):
        raise ValueError(f"R must be (n, d, d) = {(n, d, d)}, got {R.shape}")
    handle_positions = np.asarray(handle_positions, dtype=float)
    if handle_positions.shape != (len(data["handles"]), d):
        raise ValueError(f"handle_positions must be {(len(data['handles']), d)}, got {handle_positions.shape}")
    V, F, C = data["V"], data["F"], data["C"]
    R_avg = (R[F[:, 0]] + R[F[:, 1]] + R[F[:, 2]]) / 3.0
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    y = C[:, :, None] * np.matmul(e, np.swapaxes(R_avg, 1, 2))
    B = data["G"] @ y.reshape(-1, d)
    U = np.zeros((n, d))
    U[data["handles"]] = handle_positions
    free = data["free"]
    if free.size:
        rhs = B[free] - data["A_fh"] @ handle_positions
        for c in range(d):
            U[free, c] = data["solve"](rhs[:, c])
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
    if int(iterations) != iterations or iterations < 0:
        raise ValueError(f"iterations must be a non-negative integer, got {iterations}")
    V, F, C = data["V"], data["F"], data["C"]
    if U0 is None:
        U = V.copy()
    else:
        U = np.array(U0, dtype=float)
        if U.shape != V.shape:
            raise ValueError(f"U0 must have shape {V.shape}, got {U.shape}")
    handle_positions = np.asarray(handle_positions, dtype=float)
    if handle_positions.shape != (len(data["handles"]), data["d"]):
        raise ValueError(f"handle_positions must be {(len(data['handles']), data['d'])}, got {handle_positions.shape}")
    U[data["handles"]] = handle_positions
    energies = np.zeros(int(iterations))
    for it in range(int(iterations)):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        energies[it] = arap_energy(V, U, F, C, R)
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
    n, d = data["n"], data["d"]
    R = np.zeros((n, d, d))
    for a in range(d):
        R[:, a, a] = 1.0
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
