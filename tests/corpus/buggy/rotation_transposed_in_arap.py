NOTEBOOK = "03_arap"
DESCRIPTION = "optimal_rotation() in the ARAP notebook returns U D Ṽᵀ, the transposed rotation"
SOLUTIONS = {
    "optimal_rotation": '''import numpy as np


def optimal_rotation(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, dtype=float))
    D = np.ones(U.shape[:-1])
    D[..., -1] = np.linalg.det(U @ Vt)
    return (U * D[..., None, :]) @ Vt
''',
}
# optimal_rotation is graded in 02 only; arap_rotations and arap_solve call it and are judged
# with the student's own rotations (a bug is charged once): nothing is lost here
LOSES = set()
