ASSIGNMENT = "smoothing"
NOTEBOOK = "00_laplacian_smoothing"
DESCRIPTION = "uniform_laplacian() sums the edges of every triangle: an interior edge (in two triangles) gets weight 2"
SOLUTIONS = {
    "uniform_laplacian": '''import numpy as np
import scipy.sparse as sp


def uniform_laplacian(V, F):
    n = len(V)
    F = np.asarray(F)
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError("F must be (f, 3)")
    if F.min() < 0 or F.max() >= n:
        raise ValueError("F indexes a vertex outside V")
    i = np.concatenate([F[:, 0], F[:, 1], F[:, 2]])
    j = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    # coo_matrix sums duplicate entries: both triangles of an edge add 1
    A = sp.coo_matrix((np.ones(2 * len(i)), (np.r_[i, j], np.r_[j, i])), shape=(n, n)).tocsr()
    return A - sp.diags(np.asarray(A.sum(axis=1)).ravel())
''',
}
LOSES = {"uniform_laplacian"}
