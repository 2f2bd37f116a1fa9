NOTEBOOK = "06_fast"
DESCRIPTION = "fast_global_step() builds the right-hand side with R_c instead of R_cᵀ: B = Σ_c P_cᵀ R_c"
SOLUTIONS = {
    "fast_global_step": '''import numpy as np
import scipy.linalg


def fast_global_step(data, R, fixed_transforms):
    d, m = data.V.shape[1], data.W.shape[1]
    R, fixed_transforms = np.asarray(R, dtype=float), np.asarray(fixed_transforms, dtype=float)
    Tc = np.empty((m, d + 1, d))
    Tc[data.fixed] = np.einsum("ab,jcb->jac", data.to_centred, fixed_transforms)
    B = np.einsum("caN,cab->Nb", data.covariance_operator, R)
    rhs = B[data.free_rows] - data.quadratic_free_fixed @ Tc[data.fixed].reshape(-1, d)
    Tc[data.free] = scipy.linalg.cho_solve(data.solver, rhs).reshape(-1, d + 1, d)
    T = np.einsum("ab,jbc->jca", data.from_centred, Tc)
    T[data.fixed] = fixed_transforms
    return T
''',
}
LOSES = {"fast_global_step", "fast_precompute", "fast_solve"}
