NOTEBOOK = "06_fast"
DESCRIPTION = "fast_global_step() keeps the free handles' linear parts at the identity and solves only for their translations"
SOLUTIONS = {
    "fast_global_step": '''import numpy as np


def fast_global_step(data, R, fixed_transforms):
    d, m = data.V.shape[1], data.W.shape[1]
    R, fixed_transforms = np.asarray(R, dtype=float), np.asarray(fixed_transforms, dtype=float)
    T = np.tile(np.eye(d, d + 1), (m, 1, 1))
    T[data.fixed] = fixed_transforms
    Tc = np.einsum("ab,jcb->jac", data.to_centred, T).reshape(-1, d)
    B = np.einsum("cbN,cab->Na", data.covariance_operator, R)
    moving = data.free_rows.reshape(-1, d + 1)[:, d]  # the translation row of each free handle
    kept = np.setdiff1d(np.arange(len(Tc)), moving)
    Q = data.quadratic
    Tc[moving] = np.linalg.solve(Q[np.ix_(moving, moving)], B[moving] - Q[np.ix_(moving, kept)] @ Tc[kept])
    T = np.einsum("ab,jbc->jca", data.from_centred, Tc.reshape(m, d + 1, d))
    T[data.fixed] = fixed_transforms
    return T
''',
}
LOSES = {"fast_global_step", "fast_precompute", "fast_solve"}
