NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_arap_precompute() keeps the signed volumes, so B pulls negatively oriented tetrahedra the wrong way"
SOLUTIONS = {
    "tet_arap_precompute": '''import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def tet_arap_precompute(V, T, handles):
    V, T = np.array(V, dtype=float), np.array(T, dtype=np.int64)
    handles = np.array(handles, dtype=np.int64).reshape(-1)
    if handles.size == 0 or handles.min() < 0 or handles.max() >= len(V) or len(np.unique(handles)) != handles.size:
        raise ValueError(f"handles must be distinct vertex indices in range({len(V)}), at least one")
    free = np.setdiff1d(np.arange(len(V)), handles)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    rows = np.linalg.inv(D)
    K = -sp.csr_matrix(tet_cotangent_laplacian(V, T))
    return types.SimpleNamespace(
        V=V, T=T, handles=handles, free=free,
        volumes=tet_volumes(V, T),
        gradients=np.concatenate([-rows.sum(axis=1, keepdims=True), rows], axis=1),
        K_fh=K[free][:, handles],
        K_ff=spla.splu(K[free][:, free].tocsc()),
    )
''',
}
LOSES = {"tet_arap_precompute", "tet_arap_global_step"}
