NOTEBOOK = "03_arap"
DESCRIPTION = "cotangent_laplacian() puts +Σ_j L_ij on the diagonal instead of -Σ_j L_ij"
SOLUTIONS = {
    "cotangent_laplacian": '''import numpy as np
import scipy.sparse as sp


def cotangent_laplacian(V, F):
    F = np.asarray(F)
    C = cotangent_weights(V, F)
    n = len(V)
    i = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    j = np.concatenate([F[:, 2], F[:, 0], F[:, 1]])
    c = np.concatenate([C[:, 0], C[:, 1], C[:, 2]])
    W = sp.coo_matrix((np.r_[c, c], (np.r_[i, j], np.r_[j, i])), shape=(n, n)).tocsr()
    return (W + sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()
''',
}
# everything that factorizes or applies L
LOSES = {"cotangent_laplacian"}
