NOTEBOOK = "06_fast"
DESCRIPTION = "rotation_clusters() labels every row by its nearest k-means++ seed and stops: no Lloyd iterations, not a fixed point"
SOLUTIONS = {
    "rotation_clusters": '''import numpy as np


def rotation_clusters(W, k, seed=0):
    W = np.asarray(W, dtype=float)
    rng = np.random.default_rng(seed)
    centres = [W[rng.integers(len(W))]]
    nearest = np.sum((W - centres[0]) ** 2, axis=1)
    for _ in range(k - 1):
        centres.append(W[rng.choice(len(W), p=nearest / nearest.sum())])
        nearest = np.minimum(nearest, np.sum((W - centres[-1]) ** 2, axis=1))
    distances = np.sum((W[:, None, :] - np.array(centres)[None]) ** 2, axis=2)
    return distances.argmin(axis=1)
''',
}
LOSES = {"rotation_clusters"}
