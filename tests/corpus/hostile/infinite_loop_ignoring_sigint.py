NOTEBOOK = "01_shape_matching"
STATUS = "graded-with-incidents"
DESCRIPTION = "the solution cell of optimal_orthogonal ignores SIGINT and loops forever after the def"
SOLUTIONS = {
    "optimal_orthogonal": '''import signal

import numpy as np


def optimal_orthogonal(S):
    U, _, Vt = np.linalg.svd(S)
    return Vt.T @ U.T


signal.signal(signal.SIGINT, signal.SIG_IGN)
while True:
    pass
''',
}
# the cell never finishes, so its definition is not replayed after the restart
LOSES = {"optimal_orthogonal", "orthogonal_align"}
