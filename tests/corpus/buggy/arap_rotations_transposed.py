NOTEBOOK = "03_arap"
DESCRIPTION = "arap_rotations() returns each R_i transposed (R_iᵀ = R_i⁻¹ rotates the wrong way)"
SOLUTIONS = {
    "arap_rotations": '''import numpy as np


def arap_rotations(V, U, F, C):
    return np.swapaxes(optimal_rotation(arap_covariances(V, U, F, C)), -1, -2)
''',
}
# arap_solve calls arap_rotations and is judged with the student's own rotations: a bug is charged once
LOSES = {"arap_rotations"}
