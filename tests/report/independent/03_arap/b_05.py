NOTEBOOK = "03_arap"
DESCRIPTION = "loop student who builds sparse matrices with scipy.sparse.lil_matrix entry by entry; per-triangle python loops"
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
    S = np.asarray(S, dtype=float)
    if S.ndim == 2:
        U_, s, Vh = np.linalg.svd(S)
        R = Vh.T @ U_.T
        if np.linalg.det(R) < 0:
            Vh[-1, :] = -Vh[-1, :]
            R = Vh.T @ U_.T
        return R
    out = np.empty_like(S)
    for i in range(S.shape[0]):
        out[i] = optimal_rotation(S[i])
    return out
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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    C = np.zeros((len(F), 3))
    for t in range(len(F)):
        for k in range(3):
            p = V[F[t, k]]
            a = V[F[t, (k + 1) % 3]] - p
            b = V[F[t, (k + 2) % 3]] - p
            if len(p) == 2:
                cr = abs(a[0] * b[1] - a[1] * b[0])
            else:
                cr = np.linalg.norm(np.cross(a, b))
            C[t, k] = 0.5 * np.dot(a, b) / cr
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
    F = np.asarray(F)
    n = len(V)
    C = cotangent_weights(V, F)
    L = sp.lil_matrix((n, n))
    for t in range(len(F)):
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            c = C[t, k]
            L[i, j] += c
            L[j, i] += c
            L[i, i] -= c
            L[j, j] -= c
    return L.tocsr()
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F)
    n, d = V.shape
    S = np.zeros((n, d, d))
    for t in range(len(F)):
        St = np.zeros((d, d))
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            St += C[t][k] * np.outer(V[i] - V[j], U[i] - U[j])
        for corner in F[t]:
            S[corner] += St
    return S
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
    S = arap_covariances(V, U, F, C)
    return optimal_rotation(S)
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
    V = np.asarray(V, dtype=float)
    U = np.asarray(U, dtype=float)
    F = np.asarray(F)
    R = np.asarray(R, dtype=float)
    E = 0.0
    for t in range(len(F)):
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            e = V[i] - V[j]
            e2 = U[i] - U[j]
            for corner in F[t]:
                r = e2 - R[corner] @ e
                E += C[t][k] * np.dot(r, r)
    return float(E)
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
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    handles = np.asarray(handles, dtype=np.int64)
    n = len(V)
    if len(handles) == 0:
        raise ValueError("no handles")
    seen = set()
    for h in handles:
        if h < 0 or h >= n:
            raise ValueError("handle out of range")
        if h in seen:
            raise ValueError("repeated handle")
        seen.add(h)
    C = cotangent_weights(V, F)
    L = cotangent_laplacian(V, F)
    free = np.array([i for i in range(n) if i not in seen], dtype=np.int64)
    # position of every vertex among the free ones
    where = -np.ones(n, dtype=np.int64)
    where[free] = np.arange(len(free))
    hwhere = {}
    for a, h in enumerate(handles):
        hwhere[h] = a
    A = sp.lil_matrix((len(free), len(free)))
    Afh = sp.lil_matrix((len(free), len(handles)))
    Lcoo = L.tocoo()
    for i, j, val in zip(Lcoo.row, Lcoo.col, Lcoo.data):
        if where[i] < 0:
            continue
        if where[j] >= 0:
            A[where[i], where[j]] -= val
        else:
            Afh[where[i], hwhere[j]] -= val
    data = types.SimpleNamespace()
    data.V = V
    data.F = F
    data.C = C
    data.L = L
    data.handles = handles
    data.free = free
    data.Afh = Afh.tocsr()
    data.lu = spla.splu(A.tocsc())
    return data
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
    V, F, C = data.V, data.F, data.C
    R = np.asarray(R, dtype=float)
    hp = np.asarray(handle_positions, dtype=float)
    n, d = V.shape
    B = np.zeros((n, d))
    for t in range(len(F)):
        Rt = (R[F[t, 0]] + R[F[t, 1]] + R[F[t, 2]]) / 3
        for k in range(3):
            i = F[t, (k + 1) % 3]
            j = F[t, (k + 2) % 3]
            v = C[t, k] * (Rt @ (V[i] - V[j]))
            B[i] += v
            B[j] -= v
    U = np.zeros((n, d))
    U[data.handles] = hp
    rhs = B[data.free] - data.Afh @ hp
    U[data.free] = data.lu.solve(rhs)
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
    if U0 is None:
        U = np.array(data.V, dtype=float)
    else:
        U = np.array(U0, dtype=float)
    U[data.handles] = handle_positions
    energies = []
    for k in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)
        U = arap_global_step(data, R, handle_positions)
        E = arap_energy(data.V, U, data.F, data.C, R)
        energies.append(E)
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
    data = arap_precompute(V, F, handles)
    n, d = data.V.shape
    R = np.zeros((n, d, d))
    for i in range(n):
        R[i] = np.identity(d)
    return arap_global_step(data, R, handle_positions)
''',
}
LOSES = set()
