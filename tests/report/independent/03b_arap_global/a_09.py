import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
from scipy.sparse.linalg import splu


def _check_handles(h, n):
    if h.size == 0:
        raise ValueError("handles must not be empty")
    if np.unique(h).size != h.size:
        raise ValueError("handles must not repeat a vertex")
    if h.min() < 0 or h.max() >= n:
        raise ValueError("handles must be vertex indices in range(n)")


def _free(h, n):
    return np.setdiff1d(np.arange(n), h)


def _block(K, rows, cols):
    return K[rows][:, cols]


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
    V, F, h = _arr(V), _idx(F), _idx(handles).ravel()
    _check_handles(h, len(V))
    free = _free(h, len(V))
    K = (-cotangent_laplacian(V, F)).tocsr()
    return {"V": V, "F": F, "C": cotangent_weights(V, F), "h": h, "free": free,
            "Kfh": _block(K, free, h), "lu": splu(_block(K, free, free).tocsc())}
''',
    'arap_global_step': r'''import numpy as np


def _mean_rot(R, F):
    return _arr(R)[F].mean(axis=1)


def _rhs(data, R):
    V, F = data["V"], data["F"]
    y = data["C"][:, :, None] * _rotate(_mean_rot(R, F), _edges(V, F))
    B = np.zeros_like(V)
    np.add.at(B, _heads(F).ravel(), y.reshape(-1, V.shape[1]))
    np.subtract.at(B, _tails(F).ravel(), y.reshape(-1, V.shape[1]))
    return B


def _solve_free(data, B, Uh):
    return data["lu"].solve(B[data["free"]] - data["Kfh"] @ Uh)


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
    Uh = _arr(handle_positions)
    U = np.empty_like(data["V"])
    U[data["h"]] = Uh
    U[data["free"]] = _solve_free(data, _rhs(data, R), Uh)
    return U
''',
    'arap_solve': r'''import numpy as np


def _start(data, U0, Uh):
    U = np.array(data["V"] if U0 is None else U0, dtype=float)
    U[data["h"]] = Uh
    return U


def _iterate(data, U, Uh):
    R = arap_rotations(data["V"], U, data["F"], data["C"])
    U = arap_global_step(data, R, Uh)
    return U, arap_energy(data["V"], U, data["F"], data["C"], R)


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
    Uh = _arr(handle_positions)
    U = _start(data, U0, Uh)
    energies = np.empty(iterations)
    for k in range(iterations):
        U, energies[k] = _iterate(data, U, Uh)
    return U, energies
''',
    'laplacian_editing': r'''import numpy as np


def _identities(n, d):
    return np.broadcast_to(np.eye(d), (n, d, d))


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
    V = _arr(V)
    return arap_global_step(arap_precompute(V, F, handles), _identities(*V.shape), handle_positions)
''',
}
LOSES = set()
