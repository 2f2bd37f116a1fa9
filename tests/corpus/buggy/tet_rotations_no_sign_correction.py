NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_arap_rotations() returns X Yᵀ of the SVD without the sign correction: inverted tetrahedra get reflections"
SOLUTIONS = {
    "tet_arap_rotations": '''import numpy as np


def tet_arap_rotations(V, U, T):
    X, _, Yt = np.linalg.svd(deformation_gradients(V, U, T))
    return X @ Yt
''',
}
LOSES = {"tet_arap_rotations"}
