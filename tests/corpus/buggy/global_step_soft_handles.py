NOTEBOOK = "03b_arap_global"
DESCRIPTION = "arap_global_step() imposes the handles with a penalty weight of 1e8 instead of fixing their rows"
SOLUTIONS = {
    "arap_global_step": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def arap_global_step(data, R, handle_positions):
    V, a, b = data.V, data.a, data.b
    R_mean = np.asarray(R, dtype=float)[data.F].mean(axis=1)
    pull = data.C.ravel()[:, None] * np.einsum("tij,tj->ti", np.repeat(R_mean, 3, axis=0), V[a] - V[b])
    B = data.D @ pull
    # the handles as stiff springs (weight 1e8) on every row instead of fixed rows
    n = len(V)
    penalty = sp.csr_matrix((np.full(len(data.handles), 1e8), (data.handles, data.handles)), shape=(n, n))
    B[data.handles] += 1e8 * np.asarray(handle_positions, dtype=float)
    return spla.spsolve((-cotangent_laplacian(V, data.F) + penalty).tocsc(), B)
''',
}
# every function whose result comes from a global step
LOSES = {"arap_global_step", "arap_precompute", "arap_solve", "laplacian_editing"}
