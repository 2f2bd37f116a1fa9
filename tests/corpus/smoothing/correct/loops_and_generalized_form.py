ASSIGNMENT = "smoothing"
NOTEBOOK = "00_laplacian_smoothing"
DESCRIPTION = (
    "Python loops over edges and triangles (a set of edges, the law of cosines), a dict of weights, "
    "M⁻¹ built as a matrix, and the implicit step as (I - h M⁻¹ L) U' = U solved column by column"
)
SOLUTIONS = {
    "uniform_laplacian": '''import numpy as np
import scipy.sparse as sp


def uniform_laplacian(V, F):
    n = len(V)
    F = np.asarray(F)
    if F.ndim != 2 or F.shape[1] != 3 or not np.issubdtype(F.dtype, np.integer):
        raise ValueError("F must be an integer (f, 3) array")
    if ((F < 0) | (F >= n)).any():
        raise ValueError("F indexes a vertex outside V")
    edges = set()
    for a, b, c in F.tolist():
        for i, j in ((a, b), (b, c), (c, a)):
            edges.add((min(i, j), max(i, j)))
    L = sp.lil_matrix((n, n))
    for i, j in edges:
        L[i, j] = L[j, i] = 1.0
        L[i, i] -= 1.0
        L[j, j] -= 1.0
    return L.tocsc()
''',
    "cotangent_matrix": '''import math

import numpy as np
import scipy.sparse as sp


def cotangent_matrix(V, F):
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    n = len(V)
    if F.ndim != 2 or F.shape[1] != 3 or not np.issubdtype(F.dtype, np.integer):
        raise ValueError("F must be an integer (f, 3) array")
    if ((F < 0) | (F >= n)).any():
        raise ValueError("F indexes a vertex outside V")
    weight = {}
    for tri in F.tolist():
        p = [np.pad(V[v], (0, 3 - V.shape[1])) for v in tri]
        area = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
        if area == 0.0:
            raise ValueError(f"triangle {tri} has zero area")
        for k in range(3):
            i, j = tri[(k + 1) % 3], tri[(k + 2) % 3]
            sq = [float(np.sum((p[(k + s + 1) % 3] - p[(k + s + 2) % 3]) ** 2)) for s in range(3)]
            cot = (sq[1] + sq[2] - sq[0]) / (4.0 * area)  # law of cosines over the area
            key = (min(i, j), max(i, j))
            weight[key] = weight.get(key, 0.0) + 0.5 * cot
    rows, cols, vals = [], [], []
    diagonal = np.zeros(n)
    for (i, j), w in weight.items():
        rows += [i, j]
        cols += [j, i]
        vals += [w, w]
        diagonal[i] -= w
        diagonal[j] -= w
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n)) + sp.diags(diagonal)
''',
    "explicit_smoothing_step": '''import numpy as np
import scipy.sparse as sp


def explicit_smoothing_step(U, L, m, h):
    U = np.array(U, dtype=float)
    m = np.asarray(m, dtype=float)
    if U.ndim != 2 or np.shape(L) != (len(U), len(U)) or m.shape != (len(U),):
        raise ValueError("U must be (n, d), L (n, n) and m (n,)")
    if (m <= 0).any() or not h >= 0 or h == float("inf"):
        raise ValueError("masses must be positive and h a finite number >= 0")
    M_inv = sp.diags(1.0 / m)
    return U + h * (M_inv @ sp.csr_matrix(L)) @ U
''',
    "implicit_smoothing_step": '''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def implicit_smoothing_step(U, L, m, h):
    U = np.array(U, dtype=float)
    m = np.asarray(m, dtype=float)
    if U.ndim != 2 or np.shape(L) != (len(U), len(U)) or m.shape != (len(U),):
        raise ValueError("U must be (n, d), L (n, n) and m (n,)")
    if (m <= 0).any() or not h >= 0 or h == float("inf"):
        raise ValueError("masses must be positive and h a finite number >= 0")
    n = len(U)
    A = sp.identity(n) - h * sp.diags(1.0 / m) @ sp.csr_matrix(L)  # M⁻¹ (M - h L), not symmetric
    solve = spla.factorized(sp.csc_matrix(A))
    return np.column_stack([solve(U[:, c]) for c in range(U.shape[1])])
''',
}
LOSES = set()
