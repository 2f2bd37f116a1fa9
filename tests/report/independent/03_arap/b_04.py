NOTEBOOK = "03_arap"
DESCRIPTION = "one big function per cell with nested helper closures; precompute stores a solve closure in a dict"
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
    def _transpose(A):
        return np.swapaxes(A, -1, -2)

    def _fix_sign(left, right_t):
        det = np.linalg.det(_transpose(right_t) @ _transpose(left))
        scale = np.ones(left.shape[:-1])
        scale[..., -1] = det
        return scale

    M = np.asarray(S, dtype=float)
    left, _, right_t = np.linalg.svd(M)
    scale = _fix_sign(left, right_t)
    return _transpose(right_t) @ (scale[..., :, None] * _transpose(left))
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
    def _cross_norm(a, b):
        if a.shape[-1] == 2:
            return np.abs(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])
        return np.linalg.norm(np.cross(a, b), axis=-1)

    def _half_cot(corner, other1, other2):
        a = other1 - corner
        b = other2 - corner
        return 0.5 * np.einsum("ij,ij->i", a, b) / _cross_norm(a, b)

    pts = np.asarray(V, dtype=float)
    tris = np.asarray(F)
    p0, p1, p2 = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    return np.column_stack([
        _half_cot(p0, p1, p2),
        _half_cot(p1, p2, p0),
        _half_cot(p2, p0, p1),
    ])
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
    def _edge_lists(tris, weights):
        rows, cols, vals = [], [], []
        for k in range(3):
            a, b = tris[:, (k + 1) % 3], tris[:, (k + 2) % 3]
            rows.extend([a, b])
            cols.extend([b, a])
            vals.extend([weights[:, k], weights[:, k]])
        return np.concatenate(rows), np.concatenate(cols), np.concatenate(vals)

    def _with_diagonal(A):
        return A - sp.diags(np.ravel(A.sum(axis=1)))

    tris = np.asarray(F)
    n = np.shape(V)[0]
    r, c, v = _edge_lists(tris, cotangent_weights(V, tris))
    off = sp.csr_matrix((v, (r, c)), shape=(n, n))
    return sp.csr_matrix(_with_diagonal(off))
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
    def _edges(X, tris):
        return np.stack([X[tris[:, (k + 2) % 3]] - X[tris[:, (k + 1) % 3]] for k in range(3)], axis=1)

    def _incidence(tris, n):
        f = len(tris)
        rows = tris.ravel()
        cols = np.repeat(np.arange(f), 3)
        return sp.csr_matrix((np.ones(3 * f), (rows, cols)), shape=(n, f))

    rest = np.asarray(V, dtype=float)
    cur = np.asarray(U, dtype=float)
    tris = np.asarray(F)
    weights = np.asarray(C, dtype=float)
    n, d = rest.shape
    per_triangle = np.einsum("fk,fka,fkb->fab", weights, _edges(rest, tris), _edges(cur, tris))
    summed = _incidence(tris, n) @ per_triangle.reshape(len(tris), d * d)
    return np.asarray(summed).reshape(n, d, d)
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
    def _local_step():
        return optimal_rotation(arap_covariances(V, U, F, C))

    return _local_step()
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
    def _edges(X, tris):
        return np.stack([X[tris[:, (k + 2) % 3]] - X[tris[:, (k + 1) % 3]] for k in range(3)], axis=1)

    def _corner_term(rot, e_rest, e_cur, weights):
        rotated = np.einsum("fab,fkb->fka", rot, e_rest)
        return np.sum(weights * np.sum((e_cur - rotated) ** 2, axis=-1))

    tris = np.asarray(F)
    rots = np.asarray(R, dtype=float)
    weights = np.asarray(C, dtype=float)
    e_rest = _edges(np.asarray(V, dtype=float), tris)
    e_cur = _edges(np.asarray(U, dtype=float), tris)
    total = 0.0
    for corner in range(3):
        total += _corner_term(rots[tris[:, corner]], e_rest, e_cur, weights)
    return float(total)
''',
}
LOSES = set()
