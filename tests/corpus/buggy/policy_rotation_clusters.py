NOTEBOOK = "06_fast"
DESCRIPTION = "rotation_clusters() seeded and run by scipy.cluster.vq.kmeans2"
SOLUTIONS = {
    "rotation_clusters": '''import numpy as np
from scipy.cluster.vq import kmeans2


def rotation_clusters(W, k, seed=0):
    W = np.asarray(W, dtype=float)
    _, labels = kmeans2(W, k, minit="++", seed=seed)
    for _ in range(100):  # kmeans2 may stop before a fixed point; finish Lloyd's iterations
        means = np.stack([W[labels == c].mean(axis=0) if np.any(labels == c) else W[c] for c in range(k)])
        new = np.argmin(((W[:, None] - means[None]) ** 2).sum(-1), axis=1)
        if np.array_equal(new, labels):
            break
        labels = new
    return labels
''',
}
LOSES = {"rotation_clusters"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "rotation_clusters")
    problems = [] if "scipy.cluster.vq.kmeans2" in test["summary"] and test["score"] == 0 else [f"rotation_clusters: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["scipy.cluster.vq.kmeans2"] else [f"policy_violations {test.get('policy_violations')!r}"])
