from tests.corpus import teaching_cell

NOTEBOOK = "06_fast"
DESCRIPTION = "fast_rotations() takes every vertex's own best rotation and projects each cluster's average rotation, instead of the rotation of the cluster's summed covariance"
SOLUTIONS = {
    "fast_rotations": '''import numpy as np


def fast_rotations(data, T):
    V, F, C, W = data.V, data.F, data.C, data.W
    n, d = V.shape
    U = lbs_matrix(V, W) @ np.asarray(T, dtype=float).transpose(0, 2, 1).reshape(-1, d)
    S = np.zeros((n, d, d))
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        outer = C[:, k, None, None] * (V[a] - V[b])[:, :, None] * (U[a] - U[b])[:, None, :]
        for corner in range(3):
            np.add.at(S, F[:, corner], outer)
    R_vertex = optimal_rotation(S)
    mean = np.zeros((int(data.clusters.max()) + 1, d, d))
    np.add.at(mean, data.clusters, R_vertex)
    # the rotation nearest to the average: maximizes tr(R meanᵀ)
    return optimal_rotation(mean.transpose(0, 2, 1))
''',
}
# This student's precompute keeps the mesh, weights and clusters too (the notebook's keeps only what its steps use).
_PRECOMPUTE = teaching_cell(NOTEBOOK, "fast_precompute")
_RETURN = "return types.SimpleNamespace("
assert _RETURN in _PRECOMPUTE, "the teaching fast_precompute changed: update this entry"
SOLUTIONS["fast_precompute"] = _PRECOMPUTE.replace(_RETURN, _RETURN + "V=V, F=F, C=C, W=W, clusters=clusters, ")
# the solve iterates with these rotations; a global step after a solve does not depend on the solve
LOSES = {"fast_rotations"}
