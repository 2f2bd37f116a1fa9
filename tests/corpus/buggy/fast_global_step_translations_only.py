NOTEBOOK = "06_fast"
DESCRIPTION = "fast_global_step() keeps the free handles' linear parts at the identity and solves only for their translations"
SOLUTIONS = {
    "fast_global_step": '''import numpy as np


def fast_global_step(data, R, fixed_transforms):
    d, m = data.d, data.m
    B = np.einsum("cij,cjr->ri", np.asarray(R, dtype=float), data.P)
    T_stack = np.tile(np.eye(d + 1, d), (m, 1))  # every handle starts at the identity [I; 0]
    T_stack[data.fixed_rows] = np.asarray(fixed_transforms, dtype=float).transpose(0, 2, 1).reshape(-1, d)
    moving = data.free_rows[data.free_rows % (d + 1) == d]  # the translation row of each free handle
    kept = np.setdiff1d(np.arange(m * (d + 1)), moving)
    Q = data.Q
    T_stack[moving] = np.linalg.solve(Q[np.ix_(moving, moving)], B[moving] - Q[np.ix_(moving, kept)] @ T_stack[kept])
    return T_stack.reshape(m, d + 1, d).transpose(0, 2, 1)
''',
}
LOSES = {"fast_global_step", "fast_precompute"}
