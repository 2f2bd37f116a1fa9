NOTEBOOK = "06_fast"
DESCRIPTION = "fast_precompute() never checks that Q_ff is positive definite: a planar mesh in 3D or a vanishing weight column gets a failed or meaningless factorization instead of the contract's ValueError"
SOLUTIONS = {
    "fast_precompute": '''import types

import numpy as np
import scipy.linalg


def fast_precompute(V, F, W, clusters, fixed):
    V, F, W = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64), np.asarray(W, dtype=float)
    clusters = np.asarray(clusters, dtype=np.int64)
    fixed = np.asarray(fixed, dtype=np.int64).reshape(-1)
    (n, d), m, k = V.shape, W.shape[1], clusters.max() + 1
    if fixed.size == 0:
        raise ValueError("fixed: at least one handle must be fixed, or a common translation of every handle costs nothing")
    if fixed.min() < 0 or fixed.max() >= m or len(np.unique(fixed)) != fixed.size:
        raise ValueError(f"fixed must be distinct handle indices in range({m}), got {fixed.tolist()}")
    C = cotangent_weights(V, F)
    A = lbs_matrix(V, W)  # U = A @ T_stack
    Q = 3.0 * A.T @ (-cotangent_laplacian(V, F) @ A)
    P = np.zeros((k, d, A.shape[1]))
    constant = 0.0
    for edge in range(3):
        a, b = F[:, (edge + 1) % 3], F[:, (edge + 2) % 3]
        e = V[a] - V[b]
        # C e (A_a - A_b) for every triangle, added to the clusters of all three corners
        triple = C[:, edge, None, None] * e[:, :, None] * (A[a] - A[b])[:, None, :]
        for corner in range(3):
            np.add.at(P, clusters[F[:, corner]], triple)
        constant += 3.0 * np.sum(C[:, edge] * np.sum(e**2, axis=1))
    rows = np.arange(m * (d + 1)).reshape(m, d + 1)  # the rows of T_stack that belong to each handle
    fixed_rows = rows[fixed].ravel()
    free_rows = np.setdiff1d(rows.ravel(), fixed_rows)
    Q_ff = Q[np.ix_(free_rows, free_rows)]
    return types.SimpleNamespace(
        d=d, m=m, fixed=fixed, fixed_rows=fixed_rows, free_rows=free_rows, Q=Q, P=P, constant=constant,
        Q_ff=scipy.linalg.cho_factor(Q_ff) if free_rows.size else None,
    )
''',
}
LOSES = {"fast_precompute"}
