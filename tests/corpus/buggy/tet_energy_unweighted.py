NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_arap_energy() sums ‖J_t - R_t‖² without the tetrahedra's volumes"
SOLUTIONS = {
    "tet_arap_energy": '''import numpy as np


def tet_arap_energy(V, U, T, R):
    J = deformation_gradients(V, U, T)
    return float(np.sum((J - np.asarray(R, dtype=float)) ** 2))
''',
}
LOSES = {"tet_arap_energy"}
