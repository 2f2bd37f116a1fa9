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
    def _check(h, n):
        if len(h) == 0:
            raise ValueError("at least one handle is needed")
        if len(set(h.tolist())) != len(h):
            raise ValueError("a handle vertex is repeated")
        if h.min() < 0 or h.max() >= n:
            raise ValueError("handle index out of range")

    def _split(A, free, fixed):
        A = A.tocsr()
        return A[free][:, free].tocsc(), A[free][:, fixed]

    rest = np.asarray(V, dtype=float)
    tris = np.asarray(F)
    h = np.asarray(handles, dtype=np.int64).reshape(-1)
    n = len(rest)
    _check(h, n)
    weights = cotangent_weights(rest, tris)
    L = cotangent_laplacian(rest, tris)
    free = np.setdiff1d(np.arange(n), h)
    K_ff, K_fh = _split(-L, free, h)
    factor = spla.splu(K_ff)

    def solve(rhs, fixed_values):
        return factor.solve(rhs - K_fh @ fixed_values)

    return {"V": rest, "F": tris, "C": weights, "L": L, "handles": h,
            "free": free, "solve": solve}
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
    def _rhs(rest, tris, weights, mean_rot):
        n, d = rest.shape
        B = np.zeros((n, d))
        for k in range(3):
            a, b = tris[:, (k + 1) % 3], tris[:, (k + 2) % 3]
            term = weights[:, k:k + 1] * np.einsum("fij,fj->fi", mean_rot, rest[a] - rest[b])
            np.add.at(B, a, term)
            np.add.at(B, b, -term)
        return B

    rest, tris, weights = data["V"], data["F"], data["C"]
    rots = np.asarray(R, dtype=float)
    fixed = np.asarray(handle_positions, dtype=float)
    mean_rot = rots[tris].sum(axis=1) / 3.0
    B = _rhs(rest, tris, weights, mean_rot)
    out = np.empty_like(rest)
    out[data["handles"]] = fixed
    out[data["free"]] = data["solve"](B[data["free"]], fixed)
    return out
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
    def _start():
        X = np.array(data["V"] if U0 is None else U0, dtype=float)
        X[data["handles"]] = handle_positions
        return X

    def _iterate(X):
        rots = arap_rotations(data["V"], X, data["F"], data["C"])
        X = arap_global_step(data, rots, handle_positions)
        return X, arap_energy(data["V"], X, data["F"], data["C"], rots)

    X = _start()
    energies = []
    for _ in range(iterations):
        X, e = _iterate(X)
        energies.append(e)
    return X, np.array(energies)
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
    def _identities(n, d):
        return np.repeat(np.eye(d)[None], n, axis=0)

    rest = np.asarray(V, dtype=float)
    data = arap_precompute(rest, F, handles)
    return arap_global_step(data, _identities(*rest.shape), handle_positions)
''',
}
LOSES = set()
