NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_arap_precompute() never checks handles: an empty, repeated or out-of-range handle gets a crash or a meaningless system instead of the contract's ValueError"
SOLUTIONS = {
    "tet_arap_precompute": '''import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def tet_arap_precompute(V, T, handles):
    V, T = np.array(V, dtype=float), np.array(T, dtype=np.int64)  # copies: later edits cannot reach the caller
    handles = np.array(handles, dtype=np.int64).reshape(-1)
    free = np.setdiff1d(np.arange(len(V)), handles)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)  # columns v_k - v_0
    rows = np.linalg.inv(D)  # rows ∇φ_1, ∇φ_2, ∇φ_3
    K = -sp.csr_matrix(tet_cotangent_laplacian(V, T))  # -L
    return types.SimpleNamespace(
        V=V, T=T, handles=handles, free=free,
        volumes=np.abs(tet_volumes(V, T)),
        gradients=np.concatenate([-rows.sum(axis=1, keepdims=True), rows], axis=1),  # (f, 4, 3): ∇φ of each corner
        K_fh=K[free][:, handles],
        K_ff=spla.splu(K[free][:, free].tocsc()),  # the same for every R and every handle position
    )
''',
}
LOSES = {"tet_arap_precompute"}
