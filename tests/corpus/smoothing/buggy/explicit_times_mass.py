ASSIGNMENT = "smoothing"
NOTEBOOK = "00_laplacian_smoothing"
DESCRIPTION = "explicit_smoothing_step() multiplies the update by the masses (M L U) instead of dividing (M⁻¹ L U)"
SOLUTIONS = {
    "explicit_smoothing_step": '''import numpy as np


def explicit_smoothing_step(U, L, m, h):
    U = np.asarray(U, dtype=float)
    m = np.asarray(m, dtype=float)
    if U.ndim != 2:
        raise ValueError("U must be (n, d)")
    n = len(U)
    if L.shape != (n, n) or m.shape != (n,):
        raise ValueError("L must be (n, n) and m (n,)")
    if not np.all(m > 0):
        raise ValueError("masses must be positive")
    if not (np.isfinite(h) and h >= 0):
        raise ValueError("h must be >= 0")
    return U + h * m[:, None] * (L @ U)
''',
}
LOSES = {"explicit_smoothing_step"}
