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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    n = V.shape[0]
    handles = np.asarray(handles, dtype=np.int64)
    if handles.size == 0:
        raise ValueError("handles is empty")
    if len(np.unique(handles)) < len(handles):
        raise ValueError("handles contains duplicates")
    if np.any((handles < 0) | (handles >= n)):
        raise ValueError("handles contains indices outside 0..n-1")
    free = np.ones(n, dtype=bool)
    free[handles] = False
    free = np.flatnonzero(free)
    C = cotangent_weights(V, F)
    D = _difference_operator(F, n)
    K = (D.T @ sp.diags(C.ravel()) @ D).tocsc()
    lu = spla.splu(K[:, free][free, :].tocsc(), permc_spec="COLAMD")
    return {"V": V, "F": F, "C": C, "D": D, "K_fh": K[:, handles][free, :].tocsr(),
            "handles": handles, "free": free, "lu": lu}
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
    V, F, D = data["V"], data["F"], data["D"]
    n, d = V.shape
    f = len(F)
    R = np.asarray(R, dtype=np.float64)
    Uh = np.asarray(handle_positions, dtype=np.float64)
    Rbar = (R[F[:, 0]] + R[F[:, 1]] + R[F[:, 2]]) / 3.0
    E0 = (D @ V).reshape(f, 3, d)
    Y = data["C"][:, :, None] * np.matmul(E0, Rbar.transpose(0, 2, 1))
    B = D.T @ Y.reshape(3 * f, d)
    U = np.zeros((n, d))
    U[data["handles"]] = Uh
    U[data["free"]] = data["lu"].solve(np.asarray(B[data["free"]] - data["K_fh"] @ Uh))
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
    U = np.array(V if U0 is None else U0, dtype=np.float64)
    U[data["handles"]] = np.asarray(handle_positions, dtype=np.float64)
    energies = np.zeros(iterations)
    for it in range(iterations):
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
    n, d = data["V"].shape
    R = np.zeros((n, d, d))
    R[:, np.arange(d), np.arange(d)] = 1.0
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
