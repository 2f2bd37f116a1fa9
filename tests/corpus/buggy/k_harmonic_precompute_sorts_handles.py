NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = (
    "k_harmonic_precompute() keeps np.unique(handles), which also sorts them: the displacements then go to the "
    "wrong handles unless the caller gave them in ascending order"
)
SOLUTIONS = {
    "k_harmonic_precompute": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def k_harmonic_precompute(Q, handles):
    Q = sp.csr_matrix(Q, dtype=float)
    n = Q.shape[0]
    handles = np.asarray(handles)
    if handles.ndim != 1 or len(handles) == 0:
        raise ValueError("handles must list at least one vertex")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handles must be vertices 0..{n - 1}")
    if len(np.unique(handles)) < len(handles):
        raise ValueError("handles repeats a vertex")
    handles = np.unique(handles)  # tidy: each once, in order
    free = np.setdiff1d(np.arange(n), handles)
    return {
        "n": n,
        "handles": handles,
        "free": free,
        "Q_fh": Q[free][:, handles],
        "solve_ff": spla.factorized(Q[free][:, free].tocsc()) if len(free) else None,
    }
''',
}
# every hidden problem gives its handles in random order; the solve takes the student's precompute object
LOSES = {"k_harmonic_precompute", "k_harmonic_solve"}
