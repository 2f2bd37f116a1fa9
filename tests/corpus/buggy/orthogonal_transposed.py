NOTEBOOK = "01_shape_matching"
DESCRIPTION = "optimal_orthogonal() returns U Ṽᵀ instead of Ũ Uᵀ (the transpose of the answer)"
SOLUTIONS = {
    "optimal_orthogonal": '''import numpy as np


def optimal_orthogonal(S):
    U, _, Vt = np.linalg.svd(np.asarray(S, dtype=float))
    return U @ Vt
''',
}
LOSES = {"optimal_orthogonal"}
