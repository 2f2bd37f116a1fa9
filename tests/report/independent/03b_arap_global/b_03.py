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
    V = np.asarray(V, float)
    F = np.asarray(F)
    h = np.asarray(handles).astype(np.int64).ravel()
    n = len(V)
    if h.size == 0 or np.unique(h).size != h.size or (h < 0).any() or (h >= n).any():
        raise ValueError("handles must be distinct, in range and non-empty")
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F).tocsr()
    mask = np.zeros(n, bool)
    mask[h] = True
    K = -L
    Kff = K[~mask][:, ~mask].tocsc()
    Kfh = K[~mask][:, h]
    return dict(V=V, F=F, C=C, L=L, handles=h, mask=mask,
                Kfh=Kfh, lu=spla.splu(Kff))
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
    V, F, C, mask = data["V"], data["F"], data["C"], data["mask"]
    n, d = V.shape
    Uh = np.asarray(handle_positions, float)
    Rbar = np.asarray(R, float)[F].mean(axis=1)
    a = np.roll(F, -1, axis=1)
    b = np.roll(F, -2, axis=1)
    x = C[..., None] * np.einsum("tij,tkj->tki", Rbar, V[a] - V[b])   # (f, 3, d)
    x = x.reshape(-1, d)
    B = np.stack([np.bincount(a.ravel(), x[:, c], minlength=n)
                  - np.bincount(b.ravel(), x[:, c], minlength=n) for c in range(d)], axis=1)
    U = np.empty((n, d))
    U[data["handles"]] = Uh
    U[~mask] = data["lu"].solve(B[~mask] - data["Kfh"] @ Uh)
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
    V, F, C = data["V"], data["F"], data["C"]
    U = V.copy() if U0 is None else np.array(U0, float)
    U[data["handles"]] = handle_positions
    energies = []
    for _ in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(V, U, F, C, R))
    return U, np.asarray(energies)
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
    n, d = np.shape(V)
    I = np.broadcast_to(np.eye(d), (n, d, d))
    return arap_global_step(arap_precompute(V, F, handles), I, handle_positions)
''',
}
LOSES = set()
