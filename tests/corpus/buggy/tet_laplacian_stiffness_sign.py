NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_cotangent_laplacian() returns the stiffness matrix K = Σ |vol| ∇φ ∇φᵀ itself, not L = -K"
SOLUTIONS = {
    "tet_cotangent_laplacian": '''import numpy as np
import scipy.sparse as sp


def tet_cotangent_laplacian(V, T):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    B = np.linalg.inv(D)
    G = np.concatenate([-B.sum(axis=1, keepdims=True), B], axis=1)
    vol = np.abs(np.linalg.det(D)) / 6
    K = vol[:, None, None] * (G @ G.transpose(0, 2, 1))
    rows, cols = np.repeat(T, 4, axis=1), np.tile(T, (1, 4))
    return sp.csr_matrix((K.ravel(), (rows.ravel(), cols.ravel())), shape=(len(V), len(V)))
''',
}
# tet_arap_precompute calls it and is judged with the student's own L (so is the global step on that precompute)
LOSES = {"tet_cotangent_laplacian"}
