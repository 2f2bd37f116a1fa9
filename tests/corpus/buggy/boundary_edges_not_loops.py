NOTEBOOK = "00_meshes"
DESCRIPTION = "boundary_loop_count() returns the number of boundary edges instead of the number of loops"
SOLUTIONS = {
    "boundary_loop_count": '''import numpy as np


def boundary_loop_count(F):
    F = np.asarray(F)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, uses = np.unique(E, axis=0, return_counts=True)
    return int(np.sum(uses == 1))
''',
}
# genus uses b from boundary_loop_count
LOSES = {"boundary_loop_count", "genus"}
