NOTEBOOK = "05_lbs"
DESCRIPTION = "dqs() blends the transform matrices with the weights (linear blend skinning under another name)"
SOLUTIONS = {
    "dqs": '''import numpy as np


def dqs(V, W, T):
    V, W, T = np.asarray(V, float), np.asarray(W, float), np.asarray(T, float)
    return np.einsum("ij,jab,ib->ia", W, T[:, :, :3], V) + W @ T[:, :, 3]
''',
}
LOSES = {"dqs"}
