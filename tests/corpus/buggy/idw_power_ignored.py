NOTEBOOK = "04_bbw"
DESCRIPTION = "inverse_distance_weights() always uses 1/d, whatever power is asked for"
SOLUTIONS = {
    "inverse_distance_weights": '''import numpy as np


def inverse_distance_weights(V, handle_points, power=2):
    D = np.linalg.norm(np.asarray(V, float)[:, None] - np.asarray(handle_points, float)[None], axis=2)
    W = np.zeros_like(D)
    on = D <= 1e-12
    hit = on.any(axis=1)
    W[hit] = on[hit]
    W[~hit] = 1.0 / D[~hit]
    return W / W.sum(axis=1, keepdims=True)
''',
}
LOSES = {"inverse_distance_weights"}
