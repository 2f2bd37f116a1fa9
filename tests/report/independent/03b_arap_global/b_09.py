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
    X = np.asarray(V, dtype=float)
    T = np.asarray(F)
    h = np.asarray(handles, dtype=np.int64).ravel()
    n = len(X)
    if h.size < 1:
        raise ValueError("empty handles")
    if np.any(h < 0) or np.any(h >= n):
        raise ValueError("handle out of range")
    if np.unique(h).size < h.size:
        raise ValueError("repeated handle")
    W = cotangent_weights(X, T)
    L = cotangent_laplacian(X, T)
    f = np.setdiff1d(np.arange(n), h)
    nf = len(f)
    # permutation: new index = position in [free, handles]
    perm = np.concatenate([f, h])
    P = sp.csr_matrix((np.ones(n), (np.arange(n), perm)), shape=(n, n))
    Lp = (P @ (-L) @ P.T).tocsr()          # [[K_ff, K_fh], [K_hf, K_hh]]
    K_ff = Lp[:nf, :nf]
    K_fh = Lp[:nf, nf:]
    return types.SimpleNamespace(V=X, F=T, C=W, L=L, handles=h, free=f, P=P, nf=nf,
                                 K_fh=K_fh, lu=spla.splu(K_ff.tocsc()))
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
    X, T, W = data.V, data.F, data.C
    n, d = X.shape
    Rs = np.asarray(R, dtype=float)
    Uh = np.asarray(handle_positions, dtype=float)
    Rm = (Rs[T[:, 0]] + Rs[T[:, 1]] + Rs[T[:, 2]]) / 3.0
    i = T[:, [1, 2, 0]].ravel()
    j = T[:, [2, 0, 1]].ravel()
    Rrep = np.repeat(Rm, 3, axis=0)
    g = W.ravel()[:, None] * np.einsum("mab,mb->ma", Rrep, X[i] - X[j])
    B = np.zeros((n, d))
    np.add.at(B, i, g)
    np.add.at(B, j, -g)
    Bp = data.P @ B                          # same permutation as the matrix
    B_f = Bp[:data.nf]
    # K_ff U_f + K_fh U_h = B_f  ->  K_ff U_f = B_f - K_fh U_h
    U_f = data.lu.solve(B_f - data.K_fh @ Uh)
    Up = np.vstack([U_f, Uh])
    return data.P.T @ Up
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
    Y = np.array(data.V, dtype=float) if U0 is None else np.array(U0, dtype=float)
    Y[data.handles] = handle_positions
    out = []
    for it in range(iterations):
        Rs = arap_rotations(data.V, Y, data.F, data.C)
        Y = arap_global_step(data, Rs, handle_positions)
        out.append(arap_energy(data.V, Y, data.F, data.C, Rs))
    return Y, np.array(out)
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
    X = np.asarray(V, dtype=float)
    n, d = X.shape
    data = arap_precompute(X, F, handles)
    eye = np.zeros((n, d, d))
    for a in range(d):
        eye[:, a, a] = 1.0
    return arap_global_step(data, eye, handle_positions)
''',
}
LOSES = set()
