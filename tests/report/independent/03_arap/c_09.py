NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 09: geometry first: side lengths, triangle areas (Heron) and corner angles (np.arccos of the law of cosines), then everything from the angles (0.5 / np.tan); lil_matrix Laplacian.'
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
    mats = np.array(S, dtype=np.float64)
    one = mats.ndim == 2
    if one:
        mats = mats[None, :, :]
    d = mats.shape[-1]
    left, sing, right_t = np.linalg.svd(mats)
    right = np.transpose(right_t, (0, 2, 1))
    left_t = np.transpose(left, (0, 2, 1))
    reflect = np.linalg.det(np.matmul(right, left_t)) < 0
    right[reflect, :, d - 1] = -right[reflect, :, d - 1]
    rots = np.matmul(right, left_t)
    if one:
        return rots[0]
    return rots
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
    pts = np.array(V, dtype=np.float64)
    tris = np.array(F, dtype=np.int64)
    # side k is the side opposite corner k
    lengths = np.zeros((len(tris), 3))
    for k in range(3):
        p = pts[tris[:, (k + 1) % 3]]
        q = pts[tris[:, (k + 2) % 3]]
        lengths[:, k] = np.sqrt(np.sum((p - q) ** 2, axis=1))
    # areas (Heron), just to make sure no triangle is degenerate
    s = lengths.sum(axis=1) / 2.0
    areas = np.sqrt(np.maximum(s * (s - lengths[:, 0]) * (s - lengths[:, 1]) * (s - lengths[:, 2]), 0.0))
    assert np.all(areas > 0), "degenerate triangle"
    # angle at corner k from the law of cosines
    angles = np.zeros((len(tris), 3))
    for k in range(3):
        opp = lengths[:, k]
        side1 = lengths[:, (k + 1) % 3]
        side2 = lengths[:, (k + 2) % 3]
        cos_angle = (side1 ** 2 + side2 ** 2 - opp ** 2) / (2.0 * side1 * side2)
        angles[:, k] = np.arccos(np.clip(cos_angle, -1.0, 1.0))
    return 0.5 * (1.0 / np.tan(angles))
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
    tris = np.array(F, dtype=np.int64)
    n = len(V)
    half_cot = cotangent_weights(V, tris)
    L = sp.lil_matrix((n, n))
    for t in range(len(tris)):
        for k in range(3):
            i = tris[t, (k + 1) % 3]
            j = tris[t, (k + 2) % 3]
            L[i, j] += half_cot[t, k]
            L[j, i] += half_cot[t, k]
    L = L.tocsr()
    L.setdiag(-np.array(L.sum(axis=1)).flatten())
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
    pts = np.array(V, dtype=np.float64)
    moved = np.array(U, dtype=np.float64)
    tris = np.array(F, dtype=np.int64)
    half_cot = np.array(C, dtype=np.float64)
    n, d = pts.shape
    tri_cov = np.zeros((len(tris), d, d))
    for k in range(3):
        i = tris[:, (k + 1) % 3]
        j = tris[:, (k + 2) % 3]
        rest = pts[j] - pts[i]
        now = moved[j] - moved[i]
        tri_cov += half_cot[:, k].reshape(-1, 1, 1) * np.matmul(rest[:, :, None], now[:, None, :])
    S = np.zeros((n, d, d))
    for corner in range(3):
        np.add.at(S, tris[:, corner], tri_cov)
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
    covs = arap_covariances(V, U, F, C)
    return optimal_rotation(covs)
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
    pts = np.array(V, dtype=np.float64)
    moved = np.array(U, dtype=np.float64)
    tris = np.array(F, dtype=np.int64)
    half_cot = np.array(C, dtype=np.float64)
    rots = np.array(R, dtype=np.float64)
    energy = 0.0
    for corner in range(3):
        rot = rots[tris[:, corner]]
        for k in range(3):
            i = tris[:, (k + 1) % 3]
            j = tris[:, (k + 2) % 3]
            rest = pts[j] - pts[i]
            now = moved[j] - moved[i]
            diff = now - np.matmul(rot, rest[:, :, None])[:, :, 0]
            energy += np.sum(half_cot[:, k] * (diff ** 2).sum(axis=1))
    return float(energy)
''',
}
LOSES = set()
