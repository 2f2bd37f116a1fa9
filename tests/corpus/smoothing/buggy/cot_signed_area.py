ASSIGNMENT = "smoothing"
NOTEBOOK = "00_laplacian_smoothing"
DESCRIPTION = "cotangent_matrix() divides by the signed 2D cross product: clockwise triangles get negated weights"
SOLUTIONS = {
    "cotangent_matrix": '''import numpy as np
import scipy.sparse as sp


def cotangent_matrix(V, F):
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    n = len(V)
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError("F must be (f, 3)")
    if F.min() < 0 or F.max() >= n:
        raise ValueError("F indexes a vertex outside V")
    rows, cols, weights = [], [], []
    for k in range(3):
        o, i, j = F[:, k], F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        a, b = V[i] - V[o], V[j] - V[o]
        if V.shape[1] == 2:
            cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        else:
            cross = np.linalg.norm(np.cross(a, b), axis=1)
        if np.any(cross == 0):
            raise ValueError("zero-area triangle")
        half_cot = 0.5 * np.sum(a * b, axis=1) / cross
        rows += [i, j]
        cols += [j, i]
        weights += [half_cot, half_cot]
    W = sp.coo_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()
    return W - sp.diags(np.asarray(W.sum(axis=1)).ravel())
''',
}
LOSES = {"cotangent_matrix"}
