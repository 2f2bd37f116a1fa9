NOTEBOOK = "03b_arap_global"
DESCRIPTION = (
    "arap_precompute() keeps np.unique(handles) to drop repeats, which also sorts them: "
    "handle_positions then go to the wrong vertices unless the handles were given in ascending order"
)
SOLUTIONS = {
    "arap_precompute": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def arap_precompute(V, F, handles):
    V, F = np.asarray(V, dtype=float), np.asarray(F)
    handles = np.unique(handles)  # each handle once
    L = sp.csr_matrix(cotangent_laplacian(V, F))
    free = np.setdiff1d(np.arange(len(V)), handles)
    return {
        "V": V, "F": F, "C": cotangent_weights(V, F), "L": L, "handles": handles, "free": free,
        "solve": spla.factorized(sp.csc_matrix(-L[free][:, free])), "L_fh": L[free][:, handles],
    }
''',
    "arap_global_step": '''import numpy as np


def arap_global_step(data, R, handle_positions):
    V, F, C = data["V"], data["F"], data["C"]
    E = V[F[:, [1, 2, 0]]] - V[F[:, [2, 0, 1]]]  # edge opposite each corner
    rotated = C[..., None] * np.einsum("tij,tkj->tki", np.asarray(R)[F].mean(axis=1), E)
    b = np.zeros_like(V)
    for k in range(3):
        np.add.at(b, F[:, (k + 1) % 3], rotated[:, k])
        np.add.at(b, F[:, (k + 2) % 3], -rotated[:, k])
    U = np.empty_like(V)
    U[data["handles"]] = handle_positions
    U[data["free"]] = data["solve"](b[data["free"]] + data["L_fh"] @ np.asarray(handle_positions, dtype=float))
    return U
''',
    "arap_solve": '''import numpy as np


def arap_solve(data, handle_positions, U0=None, iterations=10):
    V, F, C = data["V"], data["F"], data["C"]
    U = np.array(V if U0 is None else U0, dtype=float)
    U[data["handles"]] = handle_positions
    energies = []
    for _ in range(iterations):
        R = arap_rotations(V, U, F, C)
        U = arap_global_step(data, R, handle_positions)
        energies.append(arap_energy(V, U, F, C, R))
    return U, energies
''',
    "laplacian_editing": '''import numpy as np


def laplacian_editing(V, F, handles, handle_positions):
    V = np.asarray(V, dtype=float)
    identities = np.tile(np.eye(V.shape[1]), (len(V), 1, 1))
    return arap_global_step(arap_precompute(V, F, handles), identities, handle_positions)
''',
}
# Every hidden problem gives its handles in random order. The global step and the solver take the student's
# precompute object as input (its design is the student's), so they lose with it; laplacian_editing calls
# precompute and global step and is judged with their outputs.
LOSES = {"arap_global_step", "arap_precompute", "arap_solve"}
