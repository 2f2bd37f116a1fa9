NOTEBOOK = "03_arap"
DESCRIPTION = "MATLAB convert: corner indices written as mod(k,3)+1 then shifted to 0-based, triplet (I,J,Val) sparse assembly, np.add.at accumulation, spla.factorized"
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
    S = np.array(S, dtype=float)
    single = (S.ndim == 2)
    if single:
        S = S[np.newaxis, :, :]
    k, d, _ = S.shape
    R = np.zeros((k, d, d))
    for i in range(k):
        U, sig, Vt = np.linalg.svd(S[i])
        V = Vt.T
        D = np.eye(d)
        D[d - 1, d - 1] = np.linalg.det(V @ U.T)   # D(end,end) = det(V*U')
        R[i] = V @ D @ U.T
    if single:
        R = R[0]
    return R
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
    V = np.array(V, dtype=float)
    F = np.array(F, dtype=int)
    nf = F.shape[0]
    dim = V.shape[1]
    C = np.zeros((nf, 3))
    for kk in range(1, 4):                 # corners 1..3 like in matlab
        k = kk - 1
        k1 = (kk % 3) + 1 - 1              # next corner, 0-based
        k2 = ((kk + 1) % 3) + 1 - 1        # corner after that, 0-based
        a = V[F[:, k1], :] - V[F[:, k], :]
        b = V[F[:, k2], :] - V[F[:, k], :]
        dotab = np.sum(a * b, axis=1)
        if dim == 3:
            cr = np.cross(a, b)
            crossnorm = np.sqrt(np.sum(cr ** 2, axis=1))
        else:
            crossnorm = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        C[:, k] = 0.5 * dotab / crossnorm
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
    F = np.array(F, dtype=int)
    nv = np.shape(V)[0]
    C = cotangent_weights(V, F)
    I = []
    J = []
    Val = []
    for k in range(3):
        src = F[:, (k + 1) % 3]
        dst = F[:, (k + 2) % 3]
        I += [src, dst]
        J += [dst, src]
        Val += [C[:, k], C[:, k]]
    I = np.concatenate(I)
    J = np.concatenate(J)
    Val = np.concatenate(Val)
    # like L = sparse(I, J, Val, nv, nv) in matlab (duplicates get summed)
    L = sp.coo_matrix((Val, (I, J)), shape=(nv, nv)).tocsr()
    rowsum = np.array(L.sum(axis=1)).flatten()
    L = L - sp.spdiags(rowsum, 0, nv, nv)
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
    V = np.array(V, dtype=float)
    U = np.array(U, dtype=float)
    F = np.array(F, dtype=int)
    C = np.array(C, dtype=float)
    nv, dim = V.shape
    nf = F.shape[0]
    Sf = np.zeros((nf, dim, dim))
    for k in range(3):
        i1 = F[:, (k + 1) % 3]
        i2 = F[:, (k + 2) % 3]
        e = V[i2, :] - V[i1, :]
        ep = U[i2, :] - U[i1, :]
        Sf += C[:, k][:, None, None] * np.einsum('fi,fj->fij', e, ep)
    S = np.zeros((nv, dim, dim))
    np.add.at(S, F[:, 0], Sf)
    np.add.at(S, F[:, 1], Sf)
    np.add.at(S, F[:, 2], Sf)
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
    R = optimal_rotation(S)
    return R
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
    V = np.array(V, dtype=float)
    U = np.array(U, dtype=float)
    F = np.array(F, dtype=int)
    C = np.array(C, dtype=float)
    R = np.array(R, dtype=float)
    E = 0.0
    for k in range(3):
        i1 = F[:, (k + 1) % 3]
        i2 = F[:, (k + 2) % 3]
        e = V[i2, :] - V[i1, :]
        ep = U[i2, :] - U[i1, :]
        for c in range(3):                 # the three corners, each with its own rotation
            Ri = R[F[:, c]]
            diff = ep - np.einsum('fij,fj->fi', Ri, e)
            E = E + np.sum(C[:, k] * np.sum(diff ** 2, axis=1))
    return float(E)
''',
}
LOSES = set()
