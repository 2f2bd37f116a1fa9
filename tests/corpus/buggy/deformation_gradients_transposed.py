NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "deformation_gradients() returns Jᵀ (D⁻ᵀ D'ᵀ); the student's rotations and energy use it, so they fail too"
SOLUTIONS = {
    "deformation_gradients": '''import numpy as np


def deformation_gradients(V, U, T):
    V, U, T = np.asarray(V, dtype=float), np.asarray(U, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    D_deformed = np.stack([U[T[:, k]] - U[T[:, 0]] for k in (1, 2, 3)], axis=2)
    return (D_deformed @ np.linalg.inv(D)).transpose(0, 2, 1)
''',
}
LOSES = {"deformation_gradients"}
