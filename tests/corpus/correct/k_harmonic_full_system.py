NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "the k-harmonic solve as one n x n system whose handle rows are replaced by identity rows (libigl's other way), and Q_k by repeated solves with M"
SOLUTIONS = {
    "k_harmonic_operator": '''import numpy as np
import scipy.sparse as sp


def k_harmonic_operator(L, M, k):
    if isinstance(k, bool) or not float(k).is_integer() or k < 1:
        raise ValueError("k must be a positive integer")
    K = -sp.csc_matrix(L, dtype=float)
    masses = sp.csc_matrix(M, dtype=float).diagonal()
    Q = K.copy()
    for _ in range(int(k) - 1):
        Q = Q @ sp.diags(1.0 / masses) @ K  # M⁻¹ K is K's rows divided by the masses
    return Q.tocsr()
''',
    "k_harmonic_precompute": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


class Precomputed:
    def __init__(self, Q, handles):
        Q = sp.lil_matrix(Q, dtype=float)
        self.n = Q.shape[0]
        self.handles = np.array(handles, dtype=int).reshape(-1)
        if self.handles.size == 0 or self.handles.min() < 0 or self.handles.max() >= self.n:
            raise ValueError("handles must be at least one vertex index in range")
        if np.unique(self.handles).size != self.handles.size:
            raise ValueError("a handle is repeated")
        Q[self.handles, :] = 0.0
        for h in self.handles:
            Q[h, h] = 1.0  # the handle's row now reads d_h = given
        self.lu = spla.splu(Q.tocsc())


def k_harmonic_precompute(Q, handles):
    return Precomputed(Q, handles)
''',
    "k_harmonic_solve": '''import numpy as np


def k_harmonic_solve(data, handle_displacements):
    D_h = np.asarray(handle_displacements, dtype=float)
    rhs = np.zeros((data.n, D_h.shape[1]))
    rhs[data.handles] = D_h
    D = data.lu.solve(rhs)
    D[data.handles] = D_h  # exactly as given, not as solved
    return D
''',
}
LOSES = set()
