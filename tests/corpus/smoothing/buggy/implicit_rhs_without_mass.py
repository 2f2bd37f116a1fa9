ASSIGNMENT = "smoothing"
NOTEBOOK = "00_laplacian_smoothing"
DESCRIPTION = "implicit_smoothing_step() solves (M - h L) U' = U: the right-hand side lacks M"
SOLUTIONS = {
    "implicit_smoothing_step": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def implicit_smoothing_step(U, L, m, h):
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
    A = (sp.diags(m) - h * sp.csr_matrix(L)).tocsc()
    return np.reshape(spla.spsolve(A, U), U.shape)
''',
}
LOSES = {"implicit_smoothing_step"}
