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
}
LOSES = set()
