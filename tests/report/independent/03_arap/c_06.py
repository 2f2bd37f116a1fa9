NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 06: scipy-heavy; factorizes (-L)_ff with scipy.sparse.linalg.splu and keeps the SuperLU object in a small class, solves all coordinates at once with lu.solve.'
SOLUTIONS = {
    "optimal_rotation": r'''import numpy as np


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
    U, s, Vt = np.linalg.svd(S)
    R = np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)
    bad = np.linalg.det(R) < 0
    if np.any(bad):
        if S.ndim == 2:
            Vt[-1, :] *= -1.0
        else:
            Vt[bad, -1, :] *= -1.0
        R = np.swapaxes(Vt, -1, -2) @ np.swapaxes(U, -1, -2)
    return R
''',
    "cotangent_weights": r'''import numpy as np


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
    X = np.asarray(V, dtype=float)
    T = np.asarray(F, dtype=np.int64)
    out = np.zeros((T.shape[0], 3))
    for k in range(3):
        o = X[T[:, k]]
        u = X[T[:, (k + 1) % 3]] - o
        v = X[T[:, (k + 2) % 3]] - o
        if X.shape[1] == 3:
            sin_part = np.linalg.norm(np.cross(u, v), axis=1)
        else:
            sin_part = np.abs(np.linalg.det(np.stack([u, v], axis=1)))
        out[:, k] = np.einsum("ij,ij->i", u, v) / sin_part
    return 0.5 * out
''',
    "cotangent_laplacian": r'''import numpy as np
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
    T = np.asarray(F, dtype=np.int64)
    n = np.shape(V)[0]
    W = cotangent_weights(V, T)
    L = sp.csc_matrix((n, n))
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        L = L + sp.csc_matrix((W[:, k], (i, j)), shape=(n, n)) + sp.csc_matrix((W[:, k], (j, i)), shape=(n, n))
    L = L - sp.diags(np.ravel(L.sum(axis=0)), format="csc")
    return L
''',
    "arap_covariances": r'''import numpy as np


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
    X = np.asarray(V, dtype=float)
    Y = np.asarray(U, dtype=float)
    T = np.asarray(F, dtype=np.int64)
    W = np.asarray(C, dtype=float)
    n, d = X.shape
    S = np.zeros((n, d, d))
    tri = np.zeros((T.shape[0], d, d))
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        tri += np.einsum("t,ta,tb->tab", W[:, k], X[i] - X[j], Y[i] - Y[j])
    for c in range(3):
        np.add.at(S, T[:, c], tri)
    return S
''',
    "arap_rotations": r'''def arap_rotations(V, U, F, C):
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
    "arap_energy": r'''import numpy as np


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
    X = np.asarray(V, dtype=float)
    Y = np.asarray(U, dtype=float)
    T = np.asarray(F, dtype=np.int64)
    W = np.asarray(C, dtype=float)
    Rot = np.asarray(R, dtype=float)
    energy = 0.0
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        e = X[i] - X[j]
        e_def = Y[i] - Y[j]
        for c in range(3):
            res = e_def - np.einsum("tab,tb->ta", Rot[T[:, c]], e)
            energy += np.dot(W[:, k], np.einsum("ta,ta->t", res, res))
    return float(energy)
''',
    "arap_precompute": r'''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


class ArapData:
    pass


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
    data = ArapData()
    data.V = np.asarray(V, dtype=float)
    data.F = np.asarray(F, dtype=np.int64)
    h = np.asarray(handles, dtype=np.int64).ravel()
    n = data.V.shape[0]
    if h.size < 1:
        raise ValueError("need at least one handle")
    if np.any((h < 0) | (h >= n)):
        raise ValueError("handle index out of range")
    if np.unique(h).size < h.size:
        raise ValueError("duplicate handles")
    data.handles = h
    mask = np.ones(n, dtype=bool)
    mask[h] = False
    data.free = np.nonzero(mask)[0]
    data.C = cotangent_weights(data.V, data.F)
    data.L = sp.csc_matrix(cotangent_laplacian(data.V, data.F))
    K = -data.L
    data.K_fh = K[data.free, :][:, h]
    data.lu = spla.splu(sp.csc_matrix(K[data.free, :][:, data.free]))
    return data
''',
    "arap_global_step": r'''import numpy as np


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
    Rot = np.asarray(R, dtype=float)
    Uh = np.asarray(handle_positions, dtype=float)
    X, T, W = data.V, data.F, data.C
    Rm = (Rot[T[:, 0]] + Rot[T[:, 1]] + Rot[T[:, 2]]) / 3.0
    B = np.zeros(X.shape)
    for k in range(3):
        i = T[:, (k + 1) % 3]
        j = T[:, (k + 2) % 3]
        r = W[:, k][:, None] * np.einsum("tab,tb->ta", Rm, X[i] - X[j])
        np.add.at(B, i, r)
        np.add.at(B, j, -r)
    rhs = B[data.free] - data.K_fh @ Uh
    out = np.empty(X.shape)
    out[data.handles] = Uh
    out[data.free] = data.lu.solve(rhs)
    return out
''',
    "arap_solve": r'''import numpy as np


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
    Uh = np.asarray(handle_positions, dtype=float)
    cur = np.array(data.V if U0 is None else U0, dtype=float, copy=True)
    cur[data.handles] = Uh
    energies = np.empty(iterations)
    for k in range(iterations):
        Rot = arap_rotations(data.V, cur, data.F, data.C)
        cur = arap_global_step(data, Rot, Uh)
        energies[k] = arap_energy(data.V, cur, data.F, data.C, Rot)
    return cur, energies
''',
    "laplacian_editing": r'''import numpy as np


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
    Rot = np.repeat(np.eye(d)[None], n, axis=0)
    return arap_global_step(data, Rot, handle_positions)
''',
}
LOSES = set()
