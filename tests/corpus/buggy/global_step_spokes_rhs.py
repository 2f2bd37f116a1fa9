NOTEBOOK = "03b_arap_global"
DESCRIPTION = "arap_global_step() uses the spokes-only right-hand side Σ_j ½ w_ij (R_i + R_j)(v_i - v_j) of Sorkine & Alexa"
SOLUTIONS = {
    "arap_global_step": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def arap_global_step(data, R, handle_positions):
    n, d = data.V.shape
    R = np.asarray(R, dtype=float)
    L_full = cotangent_laplacian(data.V, data.F)
    L = sp.coo_matrix(L_full)
    off = L.row != L.col
    i, j, w = L.row[off], L.col[off], L.data[off]
    spokes = 0.5 * w[:, None] * np.einsum("kab,kb->ka", R[i] + R[j], data.V[i] - data.V[j])
    b = np.zeros((n, d))
    np.add.at(b, i, spokes)
    U = np.empty((n, d))
    U[data.handles] = handle_positions
    L_free = sp.csr_matrix(L_full)[data.free]
    rhs = b[data.free] + L_free[:, data.handles] @ U[data.handles]
    U[data.free] = spla.spsolve(-L_free[:, data.free].tocsc(), rhs).reshape(len(data.free), d)
    return U
''',
}
# arap_precompute is graded through the student's own global step (its object is the student's design);
# arap_solve is judged with the student's own global step; with every R_i = I both right-hand sides
# are -L V, so Laplacian editing is unaffected
LOSES = {"arap_global_step", "arap_precompute"}
