NOTEBOOK = "01_shape_matching"
DESCRIPTION = "a solution cell prints 100 MB"
SOLUTIONS = {
    "centroid": '''import numpy as np

for _ in range(100):
    print("x" * 2**20)


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    return (w / w.sum()) @ P
''',
}
LOSES = set()
