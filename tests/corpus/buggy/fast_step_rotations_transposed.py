NOTEBOOK = "06_fast"
DESCRIPTION = "fast_global_step() builds the right-hand side with R_c instead of R_cᵀ: B = Σ_c P_cᵀ R_c"
SOLUTIONS = {
    "fast_global_step": '''import numpy as np
import scipy.linalg


def fast_global_step(data, R, fixed_transforms):
    d, m = data.d, data.m
    B = np.einsum("cji,cjr->ri", np.asarray(R, dtype=float), data.P)  # Σ_c (R_cᵀ P_c)ᵀ: R_c where R_cᵀ belongs
    T_stack = np.zeros((m * (d + 1), d))
    T_stack[data.fixed_rows] = np.asarray(fixed_transforms, dtype=float).transpose(0, 2, 1).reshape(-1, d)
    if data.free_rows.size:
        rhs = B[data.free_rows] - data.Q[np.ix_(data.free_rows, data.fixed_rows)] @ T_stack[data.fixed_rows]
        T_stack[data.free_rows] = scipy.linalg.cho_solve(data.Q_ff, rhs)
    return T_stack.reshape(m, d + 1, d).transpose(0, 2, 1)
''',
}
LOSES = {"fast_global_step", "fast_precompute"}
