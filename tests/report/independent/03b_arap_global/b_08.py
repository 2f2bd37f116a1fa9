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
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    handles = np.asarray(handles, dtype=np.int64).reshape(-1)
    n = V.shape[0]
    if handles.shape[0] == 0:
        raise ValueError("at least one handle is required")
    if np.unique(handles).shape[0] != handles.shape[0]:
        raise ValueError("handles must be distinct")
    if np.any(handles < 0) or np.any(handles >= n):
        raise ValueError("handles must be valid vertex indices")
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    assert L.shape == (n, n)
    is_free = np.ones(n, dtype=bool)
    is_free[handles] = False
    free = np.flatnonzero(is_free).astype(np.int64)
    minus_L = (-L).tocsr()
    A_ff = minus_L[free][:, free].tocsc()
    A_fh = minus_L[free][:, handles].tocsr()
    assert A_ff.shape == (free.shape[0], free.shape[0])
    assert A_fh.shape == (free.shape[0], handles.shape[0])
    factor = spla.splu(A_ff)
    return {
        "V": V, "F": F, "C": C, "L": L,
        "handles": handles, "free": free,
        "A_fh": A_fh, "factor": factor,
    }
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
    V = data["V"]
    F = data["F"]
    C = data["C"]
    handles = data["handles"]
    free = data["free"]
    n, d = V.shape
    R = np.asarray(R, dtype=np.float64)
    H = np.asarray(handle_positions, dtype=np.float64)
    assert R.shape == (n, d, d)
    assert H.shape == (handles.shape[0], d)
    R_mean = np.mean(R[F], axis=1)                   # (f, d, d)
    opp_a = np.stack([F[:, 1], F[:, 2], F[:, 0]], axis=1)
    opp_b = np.stack([F[:, 2], F[:, 0], F[:, 1]], axis=1)
    e_rest = V[opp_a] - V[opp_b]                    # (f, 3, d): from b to a
    terms = C[:, :, np.newaxis] * np.einsum("fij,fej->fei", R_mean, e_rest)
    B = np.zeros((n, d), dtype=np.float64)
    np.add.at(B, opp_a.reshape(-1), terms.reshape(-1, d))
    np.add.at(B, opp_b.reshape(-1), -terms.reshape(-1, d))
    rhs = B[free] - data["A_fh"] @ H
    assert rhs.shape == (free.shape[0], d)
    U = np.zeros((n, d), dtype=np.float64)
    U[handles] = H
    U[free] = data["factor"].solve(rhs)
    return U
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
    V = data["V"]
    H = np.asarray(handle_positions, dtype=np.float64)
    assert H.shape == (data["handles"].shape[0], V.shape[1])
    if U0 is None:
        U = V.copy()
    else:
        U = np.array(U0, dtype=np.float64)
        assert U.shape == V.shape
    U[data["handles"]] = H
    energies = np.zeros(int(iterations), dtype=np.float64)
    for it in range(int(iterations)):
        R = arap_rotations(V, U, data["F"], data["C"])
        U = arap_global_step(data, R, H)
        energies[it] = arap_energy(V, U, data["F"], data["C"], R)
    return U, energies
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
    V = np.asarray(V, dtype=np.float64)
    n, d = V.shape
    data = arap_precompute(V, F, handles)
    R = np.broadcast_to(np.eye(d, dtype=np.float64), (n, d, d)).copy()
    U = arap_global_step(data, R, handle_positions)
    assert U.shape == (n, d)
    return U
''',
}
LOSES = set()
