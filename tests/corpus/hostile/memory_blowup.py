NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs() fills 20 GB, one GiB at a time, far beyond the kernel's memory limit"
SOLUTIONS = {
    "lbs": '''import numpy as np


def lbs(V, W, T):
    chunks = [np.ones(2**27) for _ in range(20)]
    return chunks[0][: np.size(V)].reshape(np.shape(V))
''',
}
LOSES = {"lbs"}
