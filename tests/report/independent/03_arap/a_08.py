NOTEBOOK = '03_arap'
DESCRIPTION = '08 puts everything in dicts: geometry helper dicts, arap_precompute stores edges, scatter indices, identity stack and factorization'
SOLUTIONS = {
    'optimal_rotation': r'''import numpy as np


def optimal_rotation(S):
    """The rotation maximizing ``tr(R S)``, for one matrix or a stack of them.

    Parameters
    ----------
    S : (d, d) or (k, d, d) array_like of float
        Covariance matrix or matrices, ``S = Ũ Σ Ṽᵀ``.

    Returns
    -------
    R : numpy.ndarray, the shape of ``S``
        ``R = Ṽ diag(1, …, 1, det(Ṽ Ũᵀ)) Ũᵀ``: orthogonal with ``det R = +1``.
    """
    S = np.asarray(S, dtype=float)
    svd = dict(zip(("U", "s", "Vt"), np.linalg.svd(S)))
    Vm = np.swapaxes(svd["Vt"], -1, -2)
    Ut = np.swapaxes(svd["U"], -1, -2)
    flip = np.ones(S.shape[-1])
    flip[-1] = -1.0
    candidates = {"plain": Vm @ Ut, "flipped": (Vm * flip) @ Ut}
    bad = np.linalg.det(candidates["plain"]) < 0
    return np.where(np.asarray(bad)[..., None, None], candidates["flipped"], candidates["plain"])
''',
    'cotangent_weights': r'''import numpy as np


def _geometry(V, F):
    g = {"V": np.asarray(V, dtype=float), "F": np.asarray(F, dtype=np.int64)}
    g["corners"] = g["V"][g["F"]]
    g["to_next"] = g["corners"][:, [1, 2, 0]] - g["corners"]
    g["to_prev"] = g["corners"][:, [2, 0, 1]] - g["corners"]
    g["dot"] = np.sum(g["to_next"] * g["to_prev"], axis=-1)
    if g["V"].shape[1] == 3:
        g["cross"] = np.linalg.norm(np.cross(g["to_next"], g["to_prev"]), axis=-1)
    else:
        g["cross"] = np.abs(g["to_next"][..., 0] * g["to_prev"][..., 1] - g["to_next"][..., 1] * g["to_prev"][..., 0])
    return g


def cotangent_weights(V, F):
    """Half the cotangent of every triangle corner.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles, none of zero area.

    Returns
    -------
    C : (f, 3) numpy.ndarray
        ``C[t, k] = ½ cot`` of the angle at corner ``k`` of triangle ``t``: the weight of
        the opposite edge ``(F[t, (k+1)%3], F[t, (k+2)%3])``.
    """
    g = _geometry(V, F)
    return 0.5 * g["dot"] / g["cross"]
''',
    'cotangent_laplacian': r'''import numpy as np
import scipy.sparse as sp


def cotangent_laplacian(V, F):
    """The cotangent Laplacian (libigl's sign: negative semi-definite).

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        Symmetric; ``L[i, j]`` is the sum of the cotangent weights of edge ``(i, j)``,
        ``L[i, i] = -Σ_{j≠i} L[i, j]``.
    """
    n = np.shape(V)[0]
    g = _geometry(V, F)
    e = {"i": g["F"][:, [1, 2, 0]].ravel(), "j": g["F"][:, [2, 0, 1]].ravel(),
         "c": cotangent_weights(V, F).ravel()}
    W = sp.csr_matrix((e["c"], (e["i"], e["j"])), shape=(n, n))
    W = (W + W.T).tolil()
    W.setdiag(-np.asarray(W.sum(axis=1)).ravel())
    return W.tocsr()
''',
    'arap_covariances': r'''import numpy as np


def _edges(V, U, F):
    F = np.asarray(F, dtype=np.int64)
    e = {"tail": F[:, [1, 2, 0]], "head": F[:, [2, 0, 1]]}
    e["rest"] = np.asarray(V, dtype=float)[e["head"]] - np.asarray(V, dtype=float)[e["tail"]]
    e["def"] = np.asarray(U, dtype=float)[e["head"]] - np.asarray(U, dtype=float)[e["tail"]]
    return e


def arap_covariances(V, U, F, C):
    """The covariance matrix of every vertex's cell (the triangles around it).

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights, ``C[t, k]`` for the edge opposite corner ``k``.

    Returns
    -------
    S : (n, d, d) numpy.ndarray
        ``S_i = Σ_{t ∋ i} Σ_k C[t, k] e_tk e'_tkᵀ``, ``e_tk`` the rest edge opposite corner
        ``k`` and ``e'_tk`` the same edge in ``U``.
    """
    e = _edges(V, U, F)
    F = np.asarray(F, dtype=np.int64)
    n, d = np.shape(V)
    per_triangle = np.einsum("tk,tka,tkb->tab", np.asarray(C, dtype=float), e["rest"], e["def"])
    S = np.zeros((n, d, d))
    owners = F.ravel()
    for a in range(d):
        for b in range(d):
            S[:, a, b] = np.bincount(owners, weights=np.repeat(per_triangle[:, a, b], 3), minlength=n)
    return S
''',
    'arap_rotations': r'''def arap_rotations(V, U, F, C):
    """The local step: the best rotation of every vertex's cell.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.

    Returns
    -------
    R : (n, d, d) numpy.ndarray
        ``R_i = optimal_rotation(S_i)`` with ``S = arap_covariances(V, U, F, C)``.
    """
    return optimal_rotation(arap_covariances(V, U, F, C))
''',
    'arap_energy': r'''import numpy as np


def arap_energy(V, U, F, C, R):
    """The ARAP energy of positions ``U`` measured against one rotation per vertex.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.

    Returns
    -------
    E : float
        ``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²``.
    """
    e = _edges(V, U, F)
    F = np.asarray(F, dtype=np.int64)
    R_corners = np.asarray(R, dtype=float)[F]                       # (f, 3, d, d)
    rotated = np.matmul(R_corners[:, :, None], e["rest"][:, None, :, :, None])[..., 0]   # (f, corner, edge, d)
    diff = e["def"][:, None] - rotated
    return float(np.sum(np.asarray(C, dtype=float)[:, None, :] * np.sum(diff ** 2, axis=-1)))
''',
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
