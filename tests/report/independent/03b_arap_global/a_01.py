import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
from types import SimpleNamespace
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
    n = V.shape[0]
    handles = np.asarray(handles, dtype=np.int64).ravel()
    if handles.size == 0:
        raise ValueError("at least one handle is needed, otherwise U is only determined up to translation")
    if np.unique(handles).size != handles.size:
        raise ValueError("a vertex appears twice among the handles")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handle indices must lie in [0, {n})")
    free = np.setdiff1d(np.arange(n), handles)
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    K = -L  # the stiffness matrix, positive semi-definite
    K_free = K[free][:, free].tocsc()
    K_free_handles = K[free][:, handles]
    return SimpleNamespace(V=V, F=F, C=C, L=L, handles=handles, free=free,
                           K_fh=K_free_handles, lu=splu(K_free))
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
    U_h = np.asarray(handle_positions, dtype=float)
    V, F = data.V, data.F
    d = V.shape[1]
    # only the mean rotation of each triangle matters for u
    R_mean = R[F].mean(axis=1)
    e_rest = _edge_vectors(V, F)
    w = np.einsum("tk,tab,tkb->tka", data.C, R_mean, e_rest).reshape(-1, d)
    i, j = _edge_endpoints(F)
    # B_a collects c R (v_a - v_b): +w at the head j of each edge, -w at its tail i
    B = np.zeros_like(V)
    np.add.at(B, j.ravel(), w)
    np.subtract.at(B, i.ravel(), w)
    U = np.empty_like(V)
    U[data.handles] = U_h
    U[data.free] = data.lu.solve(B[data.free] - data.K_fh @ U_h)
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
    U_h = np.asarray(handle_positions, dtype=float)
    U = data.V.copy() if U0 is None else np.array(U0, dtype=float)
    U[data.handles] = U_h
    energies = []
    for _ in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)
        U = arap_global_step(data, R, U_h)
        energies.append(arap_energy(data.V, U, data.F, data.C, R))
    return U, np.array(energies)
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
    n, d = data.V.shape
    identities = np.broadcast_to(np.eye(d), (n, d, d))
    return arap_global_step(data, identities, handle_positions)
''',
}
LOSES = set()
