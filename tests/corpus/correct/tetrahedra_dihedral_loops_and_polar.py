NOTEBOOK = "07_tetrahedra"
DESCRIPTION = (
    "tet_cotangent_laplacian() from the dihedral-angle formula l cot θ / 6 with loops into a dense matrix; "
    "tet_arap_rotations() by scipy's polar decomposition, the SVD only for reflections; volumes by the triple product"
)
SOLUTIONS = {
    "tet_volumes": '''import numpy as np


def tet_volumes(V, T):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    a, b, c = (V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3))
    return np.einsum("ij,ij->i", a, np.cross(b, c)) / 6
''',
    "tet_cotangent_laplacian": '''import numpy as np


def tet_cotangent_laplacian(V, T):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    L = np.zeros((len(V), len(V)))
    for tet in T:
        for i in range(4):
            for j in range(i + 1, 4):
                k, l = [c for c in range(4) if c not in (i, j)]
                a, b = V[tet[k]], V[tet[l]]
                axis = (b - a) / np.linalg.norm(b - a)
                ui, uj = V[tet[i]] - a, V[tet[j]] - a
                ui, uj = ui - (ui @ axis) * axis, uj - (uj @ axis) * axis
                cos = ui @ uj / (np.linalg.norm(ui) * np.linalg.norm(uj))
                w = np.linalg.norm(b - a) * cos / np.sqrt(1 - cos**2) / 6
                L[tet[i], tet[j]] += w
                L[tet[j], tet[i]] += w
    return L - np.diag(L.sum(axis=1))
''',
    "tet_arap_rotations": '''import numpy as np
from scipy.linalg import polar


def tet_arap_rotations(V, U, T):
    J = deformation_gradients(V, U, T)
    R = np.stack([polar(j)[0] for j in J])
    bad = np.linalg.det(R) < 0
    X, _, Yt = np.linalg.svd(J[bad])
    X[:, :, 2] *= -1
    R[bad] = X @ Yt
    return R
''',
}
LOSES = set()
