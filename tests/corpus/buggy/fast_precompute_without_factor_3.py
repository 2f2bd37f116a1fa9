NOTEBOOK = "06_fast"
DESCRIPTION = "fast_precompute() builds Q = Mᵀ(-L)M, forgetting that every edge counts in the cells of its triangle's three corners (Q = 3 Mᵀ(-L)M)"
SOLUTIONS = {
    "fast_precompute": '''import types

import numpy as np
import scipy.linalg
import scipy.sparse as sp


def fast_precompute(V, F, W, clusters, fixed):
    V, F, W = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64), np.asarray(W, dtype=float)
    clusters, fixed = np.asarray(clusters, dtype=np.int64), np.asarray(fixed, dtype=np.int64)
    (n, d), m, k = V.shape, W.shape[1], int(clusters.max()) + 1
    if fixed.size == 0 or fixed.min() < 0 or fixed.max() >= m:
        raise ValueError(f"fixed must be a non-empty list of handles in range({m}), got {fixed.tolist()}")
    C = cotangent_weights(V, F)
    M = lbs_matrix(V, W)
    Q = np.asarray(M.T @ -(cotangent_laplacian(V, F) @ M))
    # S_c = P_c Tstack: each (corner i, edge k) of a triangle adds C e (M_a - M_b) to the cluster of i
    E = V[np.roll(F, -1, axis=1)] - V[np.roll(F, -2, axis=1)]
    a, b = np.roll(F, -1, axis=1), np.roll(F, -2, axis=1)
    cells = np.repeat(clusters[F], 3, axis=1).reshape(-1, 3, 3)  # [t, corner, edge]
    rows = (d * cells[..., None] + np.arange(d)).ravel()
    values = np.broadcast_to((C[:, :, None] * E)[:, None], cells.shape + (d,)).ravel()
    ends = lambda x: np.broadcast_to(np.repeat(x[:, None, :, None], 3, axis=1), cells.shape + (d,)).ravel()
    G = sp.coo_matrix((np.r_[values, -values], (np.r_[rows, rows], np.r_[ends(a), ends(b)])), shape=(k * d, n)).tocsr()
    rest = np.zeros((k, d, d))
    np.add.at(rest, cells.ravel(), np.repeat((C[:, :, None, None] * E[..., None] * E[:, :, None, :])[:, None], 3, axis=1).reshape(-1, d, d))
    free = np.setdiff1d(np.arange(m), fixed)
    block = lambda h: ((d + 1) * h[:, None] + np.arange(d + 1)).ravel()
    free_rows, fixed_rows = block(free), block(fixed)
    try:
        solver = scipy.linalg.cho_factor(Q[np.ix_(free_rows, free_rows)]) if free.size else None
    except np.linalg.LinAlgError:
        raise ValueError("the free handles' transforms are not determined by the energy") from None
    return types.SimpleNamespace(
        V=V, F=F, W=W, clusters=clusters, fixed=fixed, free=free, C=C,
        to_centred=np.eye(d + 1), from_centred=np.eye(d + 1), quadratic=Q,
        covariance_operator=np.asarray(G @ M).reshape(k, d, -1), rest_covariances=rest,
        free_rows=free_rows, fixed_rows=fixed_rows, solver=solver,
        quadratic_free_fixed=Q[np.ix_(free_rows, fixed_rows)],
    )
''',
}
# fast_rotations only uses the covariance operator, which is right
LOSES = {"fast_precompute", "fast_energy", "fast_global_step", "fast_solve"}
