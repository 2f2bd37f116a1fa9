NOTEBOOK = "03b_arap_global"
DESCRIPTION = "laplacian_editing() uses the uniform (graph) Laplacian instead of the cotangent one"
SOLUTIONS = {
    "laplacian_editing": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def laplacian_editing(V, F, handles, handle_positions):
    V, F, handles = np.asarray(V, float), np.asarray(F), np.asarray(handles)
    n = len(V)
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    A = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n)).tocsr()
    A = ((A + A.T) > 0).astype(float)
    L = (A - sp.diags(np.asarray(A.sum(axis=1)).ravel())).tocsr()
    delta = L @ V
    free = np.setdiff1d(np.arange(n), handles)
    U = np.empty_like(V)
    U[handles] = handle_positions
    rhs = delta[free] - L[free][:, handles] @ U[handles]
    U[free] = spla.spsolve(L[free][:, free].tocsc(), rhs).reshape(len(free), -1)
    return U
''',
}
LOSES = {"laplacian_editing"}
