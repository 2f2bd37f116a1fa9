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
    data = {"V": np.asarray(V, dtype=float), "F": np.asarray(F, dtype=np.int64),
            "handles": np.asarray(handles, dtype=np.int64).ravel()}
    n, d = data["V"].shape
    data["n"], data["d"] = n, d
    if len(data["handles"]) == 0:
        raise ValueError("arap_precompute: handles is empty")
    if len(np.unique(data["handles"])) != len(data["handles"]):
        raise ValueError("arap_precompute: repeated handle vertex")
    if np.any(data["handles"] < 0) or np.any(data["handles"] >= n):
        raise ValueError("arap_precompute: handle index out of range")
    data["free"] = np.setdiff1d(np.arange(n), data["handles"])
    data["C"] = cotangent_weights(data["V"], data["F"])
    data["L"] = cotangent_laplacian(data["V"], data["F"]).tocsr()
    data["K"] = -data["L"]
    data["K_ff"] = data["K"][data["free"]][:, data["free"]].tocsc()
    data["K_fh"] = data["K"][data["free"]][:, data["handles"]]
    data["solve"] = factorized(data["K_ff"])
    edges = _edges(data["V"], data["V"], data["F"])
    data["tail"] = edges["tail"].ravel()
    data["head"] = edges["head"].ravel()
    data["rest_edges"] = edges["rest"]
    data["identity"] = np.tile(np.eye(d), (n, 1, 1))
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
    R = np.asarray(R, dtype=float)
    Uh = np.asarray(handle_positions, dtype=float)
    n, d = data["n"], data["d"]
    R_mean = R[data["F"]].mean(axis=1)
    pull = np.einsum("tk,tab,tkb->tka", data["C"], R_mean, data["rest_edges"]).reshape(-1, d)
    B = np.stack([np.bincount(data["head"], weights=pull[:, a], minlength=n)
                  - np.bincount(data["tail"], weights=pull[:, a], minlength=n) for a in range(d)], axis=1)
    rhs = B[data["free"]] - data["K_fh"] @ Uh
    U = np.zeros((n, d))
    U[data["handles"]] = Uh
    for a in range(d):
        U[data["free"], a] = data["solve"](np.ascontiguousarray(rhs[:, a]))
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
    U = (data["V"] if U0 is None else np.asarray(U0, dtype=float)).copy()
    U[data["handles"]] = handle_positions
    energies = []
    for k in range(iterations):
        R = arap_rotations(data["V"], U, data["F"], data["C"])
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(data["V"], U, data["F"], data["C"], R))
    return U, np.array(energies)
''',
    'laplacian_editing': r'''def laplacian_editing(V, F, handles, handle_positions):
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
    return arap_global_step(data, data["identity"], handle_positions)
''',
}
LOSES = set()
