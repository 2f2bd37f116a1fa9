NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_arap_global_step() builds B from R_tᵀ ∇φ_i instead of R_t ∇φ_i"
SOLUTIONS = {
    "tet_arap_global_step": '''import numpy as np


def tet_arap_global_step(data, R, handle_positions):
    Rt = np.transpose(np.asarray(R, dtype=float), (0, 2, 1))
    corner = data.volumes[:, None, None] * np.einsum("tab,tkb->tka", Rt, data.gradients)
    B = np.zeros_like(data.V)
    np.add.at(B, data.T.ravel(), corner.reshape(-1, 3))
    U = np.empty_like(data.V)
    U[data.handles] = handle_positions
    U[data.free] = data.K_ff.solve(B[data.free] - data.K_fh @ U[data.handles])
    return U
''',
}
# the precomputation's hidden cases run the global step on its data, as in stage 03
LOSES = {"tet_arap_global_step", "tet_arap_precompute"}
