NOTEBOOK = "04_bbw"
DESCRIPTION = "handle_constraints() numbers the handle columns from the last handle to the first"
SOLUTIONS = {
    "handle_constraints": '''import numpy as np


def handle_constraints(handles):
    m = len(handles)
    b = np.concatenate([np.atleast_1d(h) for h in handles]).astype(np.int64)
    bc = np.zeros((len(b), m))
    row = 0
    for j, h in enumerate(handles):
        k = len(np.atleast_1d(h))
        bc[row:row + k, m - 1 - j] = 1.0
        row += k
    return b, bc
''',
}
LOSES = {"handle_constraints"}
