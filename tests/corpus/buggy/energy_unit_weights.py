NOTEBOOK = "03_arap"
DESCRIPTION = "arap_energy() forgets the cotangent weights C (every edge weighs 1)"
SOLUTIONS = {
    "arap_energy": '''import numpy as np


def arap_energy(V, U, F, C, R):
    V, U, F, R = np.asarray(V, float), np.asarray(U, float), np.asarray(F), np.asarray(R, float)
    total = 0.0
    for k in range(3):
        i, j = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        e, e_def = V[i] - V[j], U[i] - U[j]
        for corner in range(3):
            r = e_def - np.einsum("tab,tb->ta", R[F[:, corner]], e)
            total += float(np.sum(r * r))
    return total
''',
}
# the notebook's arap_solve reports the student's own energies
LOSES = {"arap_energy"}
