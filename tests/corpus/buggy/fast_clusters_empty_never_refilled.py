NOTEBOOK = "06_fast"
DESCRIPTION = "rotation_clusters() starts Lloyd's iterations from k random rows (identical rows give identical centres) and never refills an empty cluster"
SOLUTIONS = {
    "rotation_clusters": '''import numpy as np


def rotation_clusters(W, k, seed=0):
    W = np.asarray(W, dtype=float)
    rng = np.random.default_rng(seed)
    centres = W[rng.choice(len(W), k, replace=False)]
    labels = None
    while True:
        new = np.sum((W[:, None, :] - centres[None]) ** 2, axis=2).argmin(axis=1)
        if labels is not None and np.array_equal(new, labels):
            return labels
        labels = new
        for c in range(k):
            if np.any(labels == c):  # an empty cluster keeps its old centre
                centres[c] = W[labels == c].mean(axis=0)
''',
}
LOSES = {"rotation_clusters"}
