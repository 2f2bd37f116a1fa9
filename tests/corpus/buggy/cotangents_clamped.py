NOTEBOOK = "03_arap"
DESCRIPTION = "cotangent_weights() clamps negative cotangents (obtuse angles) to zero to keep the Laplacian an M-matrix"
SOLUTIONS = {
    "cotangent_weights": '''import numpy as np


def cotangent_weights(V, F):
    V, F = np.asarray(V, dtype=float), np.asarray(F)
    C = np.empty(F.shape)
    for k in range(3):
        a, b, c = V[F[:, k]], V[F[:, (k + 1) % 3]], V[F[:, (k + 2) % 3]]
        u, v = b - a, c - a
        dot = np.sum(u * v, axis=1)
        if V.shape[1] == 2:
            cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        else:
            cross = np.linalg.norm(np.cross(u, v), axis=1)
        C[:, k] = np.maximum(0.5 * dot / cross, 0.0)
    return C
''',
}
# the hidden meshes have obtuse triangles, so L and every solve change
LOSES = {"cotangent_weights"}
