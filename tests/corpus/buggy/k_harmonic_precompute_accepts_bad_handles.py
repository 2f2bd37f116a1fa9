NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_precompute() never checks handles: an empty, repeated or out-of-range handle gets a crash or a meaningless system instead of the contract's ValueError"
SOLUTIONS = {
    "k_harmonic_precompute": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def k_harmonic_precompute(Q, handles):
    Q = sp.csr_matrix(Q, dtype=float)
    n = Q.shape[0]
    handles = np.asarray(handles, dtype=int)
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
LOSES = {"k_harmonic_precompute"}
