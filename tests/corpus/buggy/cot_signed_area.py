NOTEBOOK = "03_arap"
DESCRIPTION = "cotangent_weights() divides by the signed 2D cross product, so clockwise triangles get cotangents of the wrong sign"
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
            cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]  # twice the area, for counter-clockwise triangles
        else:
            cross = np.linalg.norm(np.cross(u, v), axis=1)
        C[:, k] = 0.5 * dot / cross
    return C
''',
}
# Right on counter-clockwise meshes only. Where a whole component is clockwise, L and the global step's
# right-hand side change sign together (the same U), but the local step maximizes tr(R (−S)); where
# neighbouring triangles differ in orientation, L itself is wrong and so are the global step and editing.
LOSES = {"cotangent_weights"}
