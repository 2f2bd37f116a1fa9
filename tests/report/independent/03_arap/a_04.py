NOTEBOOK = '03_arap'
DESCRIPTION = '04 einsum everywhere: Levi-Civita cross products, einsum covariances/energy/right-hand side, np.add.at with repeat'
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
    S = np.asarray(S, float)
    Us, sig, Vts = np.linalg.svd(S)
    sgn = np.sign(np.linalg.det(np.einsum("...ji,...kj->...ik", Vts, Us)))
    Vts = Vts.copy()
    Vts[..., -1, :] *= sgn[..., None]
    return np.einsum("...ji,...kj->...ik", Vts, Us)
''',
    'cotangent_weights': r'''import numpy as np


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
    F = np.asarray(F)
    P = V[F]
    a = P[:, [1, 2, 0]] - P
    b = P[:, [2, 0, 1]] - P
    dot = np.einsum("tki,tki->tk", a, b)
    if V.shape[1] == 2:
        eps = np.array([[0.0, 1.0], [-1.0, 0.0]])
        cross = np.abs(np.einsum("tki,ij,tkj->tk", a, eps, b))
    else:
        eps = np.zeros((3, 3, 3))
        eps[0, 1, 2] = eps[1, 2, 0] = eps[2, 0, 1] = 1.0
        eps[0, 2, 1] = eps[2, 1, 0] = eps[1, 0, 2] = -1.0
        cr = np.einsum("ijk,tnj,tnk->tni", eps, a, b)
        cross = np.sqrt(np.einsum("tni,tni->tn", cr, cr))
    return 0.5 * dot / cross
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
    n = len(V)
    F = np.asarray(F)
    C = cotangent_weights(V, F)
    I = np.hstack([F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel()])
    J = np.hstack([F[:, [2, 0, 1]].ravel(), F[:, [1, 2, 0]].ravel()])
    X = np.hstack([C.ravel(), C.ravel()])
    diag = np.bincount(I, weights=X, minlength=n)
    return sp.coo_matrix((np.hstack([X, -diag]), (np.hstack([I, np.arange(n)]), np.hstack([J, np.arange(n)]))),
                         shape=(n, n)).tocsr()
''',
    'arap_covariances': r'''import numpy as np


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
    V = np.asarray(V, float)
    U = np.asarray(U, float)
    F = np.asarray(F)
    n, d = V.shape
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    ep = U[F[:, [2, 0, 1]]] - U[F[:, [1, 2, 0]]]
    T = np.einsum("tk,tki,tkj->tij", C, e, ep)
    S = np.zeros((n, d, d))
    np.add.at(S, F.ravel(), np.repeat(T, 3, axis=0))
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
    V = np.asarray(V, float)
    U = np.asarray(U, float)
    F = np.asarray(F)
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    ep = U[F[:, [2, 0, 1]]] - U[F[:, [1, 2, 0]]]
    r = ep[:, None, :, :] - np.einsum("tcij,tkj->tcki", np.asarray(R, float)[F], e)
    return float(np.einsum("tk,tcki,tcki->", C, r, r))
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
    V = np.asarray(V, float)
    F = np.asarray(F)
    h = np.asarray(handles).astype(np.int64)
    n = len(V)
    if h.size == 0:
        raise ValueError("need at least one handle")
    if np.unique(h).size != h.size:
        raise ValueError("handles must be distinct")
    if (h < 0).any() or (h >= n).any():
        raise ValueError("handle index out of range")
    free = np.setdiff1d(np.arange(n), h)
    C = cotangent_weights(V, F)
    A = -cotangent_laplacian(V, F).tocsc()
    return dict(V=V, F=F, C=C, h=h, free=free, Afh=A[free][:, h],
                solve=factorized(A[free][:, free].tocsc()))
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
    V, F, C = data["V"], data["F"], data["C"]
    n, d = V.shape
    Rbar = np.einsum("tcij->tij", np.asarray(R, float)[F]) / 3.0
    e = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]
    y = np.einsum("tk,tij,tkj->tki", C, Rbar, e)
    B = np.zeros((n, d))
    np.add.at(B, F[:, [2, 0, 1]].ravel(), y.reshape(-1, d))
    np.add.at(B, F[:, [1, 2, 0]].ravel(), -y.reshape(-1, d))
    Uh = np.asarray(handle_positions, float)
    rhs = B[data["free"]] - data["Afh"] @ Uh
    U = np.empty((n, d))
    U[data["h"]] = Uh
    U[data["free"]] = np.column_stack([data["solve"](rhs[:, i]) for i in range(d)])
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
    U = np.array(data["V"] if U0 is None else U0, float)
    U[data["h"]] = handle_positions
    E = []
    for _ in range(iterations):
        R = arap_rotations(data["V"], U, data["F"], data["C"])
        U = arap_global_step(data, R, handle_positions)
        E.append(arap_energy(data["V"], U, data["F"], data["C"], R))
    return U, np.asarray(E)
''',
    'laplacian_editing': r'''import numpy as np


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
    d = np.shape(V)[1]
    return arap_global_step(arap_precompute(V, F, handles), np.einsum("n,ij->nij", np.ones(len(V)), np.eye(d)),
                            handle_positions)
''',
}
LOSES = set()
