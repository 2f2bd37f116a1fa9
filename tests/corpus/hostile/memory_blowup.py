NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs() allocates and fills 20 GB"
SOLUTIONS = {
    "lbs": '''import numpy as np


def lbs(V, W, T):
    scratch = np.ones(20 * 2**30 // 8)
    return scratch[: np.size(V)].reshape(np.shape(V))
''',
}
LOSES = {"lbs"}
