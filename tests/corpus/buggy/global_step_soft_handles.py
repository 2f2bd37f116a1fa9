NOTEBOOK = "03_arap"
DESCRIPTION = "arap_global_step() imposes the handles with a penalty weight of 1e8 instead of fixing their rows"
SOLUTIONS = {
    "arap_global_step": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def arap_global_step(data, R, handle_positions):
    n, d = data.V.shape
    R = np.asarray(R, dtype=float)
    P = np.asarray(handle_positions, dtype=float)
    # the right-hand side the exact solve uses, on every row
    b = (data.covariance_operator.T @ R.transpose(0, 2, 1).reshape(n * d, d)) / 3.0
    penalty = sp.csr_matrix((np.full(len(data.handles), 1e8), (data.handles, data.handles)), shape=(n, n))
    b[data.handles] += 1e8 * P
    return spla.spsolve((-data.L + penalty).tocsc(), b)
''',
}
# every function whose result comes from a global step
LOSES = {"arap_global_step", "arap_precompute", "arap_solve", "laplacian_editing"}
