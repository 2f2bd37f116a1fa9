"""The reference of the areas pack: one function."""

import numpy as np


def triangle_areas(V, F):
    """Area of every triangle, (m,), of vertices ``V`` (n, 2) or (n, 3) and triangles ``F`` (m, 3)."""
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    u, v = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    if V.shape[1] == 2:
        return 0.5 * np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    return 0.5 * np.linalg.norm(np.cross(u, v), axis=1)
