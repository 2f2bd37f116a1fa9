NOTEBOOK = "03_arap"
DESCRIPTION = "student who computes cotangents from edge lengths (law of cosines + Heron's area); per-corner loops, spsolve-free splu"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


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
    mats = np.asarray(S, dtype=float)
    left, sigma, right_T = np.linalg.svd(mats)
    right = np.swapaxes(right_T, -1, -2)
    left_T = np.swapaxes(left, -1, -2)
    R = right @ left_T
    bad = np.linalg.det(R) < 0
    # flip the column of the smallest singular value where R is a reflection
    corr = right.copy()
    corr[..., -1] = np.where(bad[..., None], -right[..., -1], right[..., -1])
    return corr @ left_T
''',
    "cotangent_weights": '''import numpy as np


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
    pts = np.asarray(V, dtype=float)
    tri = np.asarray(F)
    # side k is opposite corner k
    side = np.empty((len(tri), 3))
    for k in range(3):
        side[:, k] = np.linalg.norm(pts[tri[:, (k + 1) % 3]] - pts[tri[:, (k + 2) % 3]], axis=1)
    a, b, c = side[:, 0], side[:, 1], side[:, 2]
    # Heron's formula for the area
    s = 0.5 * (a + b + c)
    area = np.sqrt(np.maximum(s * (s - a) * (s - b) * (s - c), 0.0))
    sq = side ** 2
    C = np.empty_like(side)
    for k in range(3):
        # law of cosines: cos = (b^2 + c^2 - a^2) / (2bc), sin = 2A / (bc)
        # => cot = (b^2 + c^2 - a^2) / (4A), half of it:
        C[:, k] = (sq[:, (k + 1) % 3] + sq[:, (k + 2) % 3] - sq[:, k]) / (8.0 * area)
    return C
''',
    "cotangent_laplacian": '''import numpy as np
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
    tri = np.asarray(F)
    nv = len(V)
    cot = cotangent_weights(V, tri)
    L = sp.csr_matrix((nv, nv))
    for k in range(3):
        i = tri[:, (k + 1) % 3]
        j = tri[:, (k + 2) % 3]
        half = sp.csr_matrix((cot[:, k], (i, j)), shape=(nv, nv))
        L = L + half + half.T
    deg = np.asarray(L.sum(axis=0)).ravel()
    return (L - sp.diags(deg)).tocsr()
''',
    "arap_covariances": '''import numpy as np
import scipy.sparse as sp


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
    pts = np.asarray(V, dtype=float)
    cur = np.asarray(U, dtype=float)
    tri = np.asarray(F)
    cot = np.asarray(C, dtype=float)
    nv, dim = pts.shape
    tri_cov = np.zeros((len(tri), dim, dim))
    for k in range(3):
        i = tri[:, (k + 1) % 3]
        j = tri[:, (k + 2) % 3]
        tri_cov += np.einsum("t,ta,tb->tab", cot[:, k], pts[j] - pts[i], cur[j] - cur[i])
    out = np.zeros((nv, dim, dim))
    np.add.at(out, tri.ravel(), np.repeat(tri_cov, 3, axis=0))
    return out
''',
    "arap_rotations": '''def arap_rotations(V, U, F, C):
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
    "arap_energy": '''import numpy as np


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
    pts = np.asarray(V, dtype=float)
    cur = np.asarray(U, dtype=float)
    tri = np.asarray(F)
    cot = np.asarray(C, dtype=float)
    rot = np.asarray(R, dtype=float)
    energy = 0.0
    for k in range(3):
        i = tri[:, (k + 1) % 3]
        j = tri[:, (k + 2) % 3]
        rest_edge = pts[j] - pts[i]
        new_edge = cur[j] - cur[i]
        for corner in range(3):
            diff = new_edge - np.einsum("tab,tb->ta", rot[tri[:, corner]], rest_edge)
            energy += np.dot(cot[:, k], np.einsum("ta,ta->t", diff, diff))
    return float(energy)
''',
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
    pts = np.asarray(V, dtype=float)
    tri = np.asarray(F)
    fixed = np.asarray(handles, dtype=np.int64)
    nv = len(pts)
    if fixed.ndim != 1 or len(fixed) == 0:
        raise ValueError("handles must be a non-empty 1-D index array")
    if np.any((fixed < 0) | (fixed >= nv)):
        raise ValueError("handle index out of range")
    if len(np.unique(fixed)) != len(fixed):
        raise ValueError("duplicate handle index")
    cot = cotangent_weights(pts, tri)
    L = cotangent_laplacian(pts, tri)
    free = np.ones(nv, dtype=bool)
    free[fixed] = False
    free = np.nonzero(free)[0]
    stiff = (-L).tocsc()
    lu = spla.splu(stiff[free, :][:, free])
    return {"V": pts, "F": tri, "C": cot, "L": L, "fixed": fixed, "free": free,
            "coupling": stiff[free, :][:, fixed], "lu": lu}
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
    pts, tri, cot = data["V"], data["F"], data["C"]
    rot = np.asarray(R, dtype=float)
    target = np.asarray(handle_positions, dtype=float)
    nv, dim = pts.shape
    mean_rot = (rot[tri[:, 0]] + rot[tri[:, 1]] + rot[tri[:, 2]]) / 3.0
    rhs = np.zeros((nv, dim))
    for k in range(3):
        i = tri[:, (k + 1) % 3]
        j = tri[:, (k + 2) % 3]
        contrib = cot[:, k, None] * np.einsum("tab,tb->ta", mean_rot, pts[i] - pts[j])
        np.add.at(rhs, i, contrib)
        np.add.at(rhs, j, -contrib)
    result = np.zeros((nv, dim))
    result[data["fixed"]] = target
    result[data["free"]] = data["lu"].solve(rhs[data["free"]] - data["coupling"] @ target)
    return result
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
    pts = data["V"]
    cur = pts.copy() if U0 is None else np.array(U0, dtype=float, copy=True)
    cur[data["fixed"]] = handle_positions
    history = []
    for _ in range(iterations):
        rot = arap_rotations(pts, cur, data["F"], data["C"])
        cur = arap_global_step(data, rot, handle_positions)
        history.append(arap_energy(pts, cur, data["F"], data["C"], rot))
    return cur, np.array(history)
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
    pts = np.asarray(V, dtype=float)
    dim = pts.shape[1]
    identity = np.zeros((len(pts), dim, dim))
    identity[:, np.arange(dim), np.arange(dim)] = 1.0
    return arap_global_step(arap_precompute(pts, F, handles), identity, handle_positions)
''',
}
LOSES = set()
