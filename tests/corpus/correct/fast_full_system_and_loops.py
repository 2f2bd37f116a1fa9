NOTEBOOK = "06_fast"
DESCRIPTION = (
    "FAST of another design: maximin-seeded k-means, a dict of data in raw coordinates, the energy term by term, "
    "per-cluster loops in the local step, and a global step that assembles the full n-vertex right-hand side and projects it with Mᵀ"
)
SOLUTIONS = {
    "rotation_clusters": '''import numpy as np


def rotation_clusters(W, k, seed=0):
    """Lloyd's iterations from k far-apart rows (maximin seeding from a random first row)."""
    W = np.asarray(W, dtype=float)
    n = len(W)
    rng = np.random.default_rng(seed)
    chosen = [int(rng.integers(n))]
    gap = np.sum((W - W[chosen[0]]) ** 2, axis=1)
    for _ in range(k - 1):
        chosen.append(int(np.argmax(gap)))
        gap = np.minimum(gap, np.sum((W - W[chosen[-1]]) ** 2, axis=1))
    labels = np.sum((W[:, None, :] - W[chosen][None]) ** 2, axis=2).argmin(axis=1)
    cost = np.inf
    while True:
        counts = np.bincount(labels, minlength=k)
        for c in np.flatnonzero(counts == 0):
            means = np.array([W[labels == j].mean(axis=0) if counts[j] else W[0] for j in range(k)])
            spread = np.where(counts[labels] > 1, np.sum((W - means[labels]) ** 2, axis=1), -1.0)
            far = int(np.argmax(spread))
            counts[labels[far]] -= 1
            labels[far], counts[c] = c, 1
        means = np.array([W[labels == j].mean(axis=0) for j in range(k)])
        new_cost = float(np.sum((W - means[labels]) ** 2))
        if not new_cost < cost:  # nothing left to gain but rounding
            return labels
        cost = new_cost
        distances = np.sum((W[:, None, :] - means[None]) ** 2, axis=2)
        nearer = distances.min(axis=1) < distances[np.arange(n), labels]
        if not nearer.any():
            return labels
        labels = np.where(nearer, distances.argmin(axis=1), labels)
''',
    "fast_precompute": '''import numpy as np
import scipy.linalg


def fast_precompute(V, F, W, clusters, fixed):
    V, F, W = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64), np.asarray(W, dtype=float)
    clusters, fixed = np.asarray(clusters, dtype=np.int64), np.asarray(fixed, dtype=np.int64)
    d, m = V.shape[1], W.shape[1]
    if fixed.size == 0 or fixed.min() < 0 or fixed.max() >= m or len(np.unique(fixed)) < len(fixed):
        raise ValueError(f"fixed must list distinct handles in range({m}), at least one, got {fixed.tolist()}")
    M = lbs_matrix(V, W)
    Q = 3.0 * np.asarray(M.T @ -(cotangent_laplacian(V, F) @ M))
    free = np.setdiff1d(np.arange(m), fixed)
    free_rows = ((d + 1) * free[:, None] + np.arange(d + 1)).ravel()
    fixed_rows = ((d + 1) * fixed[:, None] + np.arange(d + 1)).ravel()
    try:
        factor = scipy.linalg.cho_factor(Q[np.ix_(free_rows, free_rows)]) if free.size else None
    except np.linalg.LinAlgError:
        raise ValueError("W and fixed leave the free transforms undetermined (singular global step)") from None
    return {
        "V": V, "F": F, "W": W, "C": cotangent_weights(V, F), "M": M, "Q": Q, "clusters": clusters,
        "k": int(clusters.max()) + 1, "fixed": fixed, "free": free, "free_rows": free_rows,
        "fixed_rows": fixed_rows, "factor": factor,
    }
''',
    "fast_energy": '''import numpy as np


def fast_energy(data, T, R):
    V, F, C = data["V"], data["F"], data["C"]
    d = V.shape[1]
    U = data["M"] @ np.asarray(T, dtype=float).transpose(0, 2, 1).reshape(-1, d)
    R = np.asarray(R, dtype=float)
    energy = 0.0
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        for corner in range(3):
            rotated = np.einsum("tij,tj->ti", R[data["clusters"][F[:, corner]]], V[a] - V[b])
            energy += float(np.sum(C[:, k] * np.sum((U[a] - U[b] - rotated) ** 2, axis=1)))
    return energy
''',
    "fast_rotations": '''import numpy as np


def fast_rotations(data, T):
    V, F, C = data["V"], data["F"], data["C"]
    n, d = V.shape
    U = data["M"] @ np.asarray(T, dtype=float).transpose(0, 2, 1).reshape(-1, d)
    S = np.zeros((n, d, d))
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        outer = C[:, k, None, None] * (V[a] - V[b])[:, :, None] * (U[a] - U[b])[:, None, :]
        for corner in range(3):
            np.add.at(S, F[:, corner], outer)
    R = np.empty((data["k"], d, d))
    for c in range(data["k"]):
        left, _, right = np.linalg.svd(S[data["clusters"] == c].sum(axis=0))
        if np.linalg.det(right.T @ left.T) < 0:
            right[-1] *= -1.0
        R[c] = right.T @ left.T
    return R
''',
    "fast_global_step": '''import numpy as np
import scipy.linalg


def fast_global_step(data, R, fixed_transforms):
    V, F, C = data["V"], data["F"], data["C"]
    d, m = V.shape[1], data["W"].shape[1]
    R_vertex = np.asarray(R, dtype=float)[data["clusters"]]
    # the energy's linear term -2 tr(Uᵀ B): each edge sees the rotations of its triangle's three corners
    B = np.zeros_like(V)
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        pull = C[:, k, None] * np.einsum("tij,tj->ti", R_vertex[F].sum(axis=1), V[a] - V[b])
        np.add.at(B, a, pull)
        np.add.at(B, b, -pull)
    rhs = data["M"].T @ B
    stack = np.zeros((m * (d + 1), d))
    stack[data["fixed_rows"]] = np.asarray(fixed_transforms, dtype=float).transpose(0, 2, 1).reshape(-1, d)
    if data["factor"] is not None:
        known = data["Q"][np.ix_(data["free_rows"], data["fixed_rows"])] @ stack[data["fixed_rows"]]
        stack[data["free_rows"]] = scipy.linalg.cho_solve(data["factor"], rhs[data["free_rows"]] - known)
    T = stack.reshape(m, d + 1, d).transpose(0, 2, 1).copy()
    T[data["fixed"]] = fixed_transforms
    return T
''',
    "fast_solve": '''import numpy as np


def fast_solve(data, fixed_transforms, T0=None, iterations=10):
    d, m = data["V"].shape[1], data["W"].shape[1]
    T = np.tile(np.eye(d, d + 1), (m, 1, 1)) if T0 is None else np.array(T0, dtype=float)
    T[data["fixed"]] = fixed_transforms
    energies = []
    for _ in range(iterations):
        R = fast_rotations(data, T)
        T = fast_global_step(data, R, fixed_transforms)
        energies.append(fast_energy(data, T, R))
    return T, energies
''',
}
LOSES = set()
