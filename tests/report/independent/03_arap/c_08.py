NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 08: minimalist, fewest lines that work, no comments; fancy indexing with F[:, [1, 2, 0]], one einsum per step, tuple for the data.'
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
    u, _, vt = np.linalg.svd(S)
    vt[..., -1, :] *= np.sign(np.linalg.det(u @ vt))[..., None]
    return np.swapaxes(u @ vt, -1, -2)
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
    V = np.asarray(V, float)
    a = V[F[:, [1, 2, 0]]] - V[F]
    b = V[F[:, [2, 0, 1]]] - V[F]
    x = np.cross(np.pad(a, ((0, 0), (0, 0), (0, 3 - V.shape[1]))), np.pad(b, ((0, 0), (0, 0), (0, 3 - V.shape[1]))))
    return 0.5 * (a * b).sum(-1) / np.linalg.norm(x, axis=-1)
''',
    "cotangent_laplacian": r'''import scipy.sparse as sp


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
    i, j, n = F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel(), len(V)
    W = sp.coo_matrix((cotangent_weights(V, F).ravel(), (i, j)), (n, n)).tocsr()
    W = W + W.T
    return W - sp.diags(W.sum(1).A1)
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
    V, U = np.asarray(V, float), np.asarray(U, float)
    e = lambda X: X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]
    M = np.einsum("tk,tki,tkj->tij", C, e(V), e(U))
    S = np.zeros((len(V),) + M.shape[1:])
    np.add.at(S, F, M[:, None])
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
    V, U, R = np.asarray(V, float), np.asarray(U, float), np.asarray(R, float)
    e = lambda X: X[F[:, [2, 0, 1]]] - X[F[:, [1, 2, 0]]]
    r = e(U)[:, None] - np.einsum("tcij,tkj->tcki", R[F], e(V))
    return float(np.einsum("tk,tcki->", C, r ** 2))
''',
    "arap_precompute": r'''import numpy as np
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
    V, h = np.asarray(V, float), np.asarray(handles, int)
    if h.size == 0 or len(set(h.tolist())) < h.size or h.min() < 0 or h.max() >= len(V):
        raise ValueError(handles)
    free = np.setdiff1d(np.arange(len(V)), h)
    L = cotangent_laplacian(V, F).tocsr()
    return V, np.asarray(F), cotangent_weights(V, F), h, free, L[free][:, h], spla.factorized(-L[free][:, free].tocsc())
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
    V, F, C, h, free, Lfh, solve = data
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    g = np.einsum("tk,tij,tkj->tki", C, np.asarray(R)[F].mean(1), e)
    B = np.zeros_like(V)
    np.add.at(B, F[:, [2, 0, 1]], g)
    np.add.at(B, F[:, [1, 2, 0]], -g)
    U = np.zeros_like(V)
    U[h] = handle_positions
    rhs = B[free] + Lfh @ U[h]
    U[free] = np.column_stack([solve(c) for c in rhs.T])
    return U
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
    V, F, C, h = data[:4]
    U = np.array(V if U0 is None else U0, float)
    U[h] = handle_positions
    E = []
    for _ in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        E.append(arap_energy(V, U, F, C, R))
    return U, np.array(E)
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
    return arap_global_step(arap_precompute(V, F, handles), np.tile(np.eye(np.shape(V)[1]), (len(V), 1, 1)), handle_positions)
''',
}
LOSES = set()
