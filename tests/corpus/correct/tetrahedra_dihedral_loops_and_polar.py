NOTEBOOK = "07_tetrahedra"
DESCRIPTION = (
    "tet_cotangent_laplacian() from the dihedral-angle formula l cot θ / 6 with loops into a dense matrix; "
    "tet_arap_rotations() by Newton's polar iteration written out (scipy's polar is a forbidden shortcut there: tests/corpus/buggy/policy_tet_arap_rotations.py), the SVD only for reflections and flat tetrahedra; volumes by the triple product; "
    "the tet ARAP global step as Gᵀ W vec(R) with a sparse (3f, n) gradient operator G built in a loop, data in a dict"
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


def tet_arap_rotations(V, U, T):
    J = deformation_gradients(V, U, T)
    R = np.empty_like(J)
    # det J > 0: Newton's iteration for the polar factor, X <- (g X + X^-T / g) / 2 with
    # Higham's scaling g, converges to the rotation nearest to J
    good = np.linalg.det(J) > 1e-9 * np.linalg.norm(J, axis=(1, 2)) ** 3
    X = J[good]
    for _ in range(60):
        inverse_t = np.linalg.inv(X).transpose(0, 2, 1)
        g = np.sqrt(np.linalg.norm(inverse_t, axis=(1, 2)) / np.linalg.norm(X, axis=(1, 2)))[:, None, None]
        new = 0.5 * (g * X + inverse_t / g)
        done = np.abs(new - X).max(initial=0.0) < 1e-15
        X = new
        if done:
            break
    R[good] = X
    # reflections and flat tetrahedra: the SVD, the last axis flipped where needed
    A, _, Bt = np.linalg.svd(J[~good])
    A[:, :, 2] *= np.sign(np.linalg.det(A @ Bt))[:, None]
    R[~good] = A @ Bt
    return R
''',
    "tet_arap_precompute": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def tet_arap_precompute(V, T, handles):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    handles = np.asarray(handles, dtype=int).ravel()
    if handles.size == 0 or len(set(handles.tolist())) != handles.size or handles.min() < 0 or handles.max() >= len(V):
        raise ValueError("handles must be distinct vertices of the mesh, at least one")
    rows, cols, vals, vol = [], [], [], []
    for t, tet in enumerate(T):
        D = np.column_stack([V[tet[k]] - V[tet[0]] for k in (1, 2, 3)])
        inverse = np.linalg.inv(D)
        grads = np.vstack([-inverse.sum(axis=0), inverse])  # row k: the gradient of corner k's hat function
        vol.append(abs(np.linalg.det(D)) / 6)
        for k in range(4):
            for c in range(3):
                rows.append(3 * t + c)
                cols.append(tet[k])
                vals.append(grads[k, c])
    G = sp.csr_matrix((vals, (rows, cols)), shape=(3 * len(T), len(V)))
    W = sp.diags(np.repeat(vol, 3))
    K = (G.T @ W @ G).tocsr()  # the stiffness matrix, -L
    free = np.array([i for i in range(len(V)) if i not in set(handles.tolist())], dtype=int)
    return {"G": G, "W": W, "handles": handles, "free": free, "n": len(V),
            "solve": spla.factorized(K[free][:, free].tocsc()), "K_fh": K[free][:, handles]}
''',
    "tet_arap_global_step": '''import numpy as np


def tet_arap_global_step(data, R, handle_positions):
    r = np.asarray(R, dtype=float).transpose(0, 2, 1).reshape(-1, 3)  # row 3t + c holds column c of R_t
    B = data["G"].T @ (data["W"] @ r)
    U = np.zeros((data["n"], 3))
    U[data["handles"]] = handle_positions
    rhs = B[data["free"]] - data["K_fh"] @ U[data["handles"]]
    U[data["free"]] = np.column_stack([data["solve"](rhs[:, a]) for a in range(3)])
    return U
''',
}
LOSES = set()
