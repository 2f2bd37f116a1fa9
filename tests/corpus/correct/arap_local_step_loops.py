NOTEBOOK = "03_arap"
DESCRIPTION = "the ARAP local step written with per-vertex Python loops over one-rings, rotations by SVD"
SOLUTIONS = {
    "arap_covariances": '''import numpy as np


def arap_covariances(V, U, F, C):
    V, U, F, C = np.asarray(V, float), np.asarray(U, float), np.asarray(F), np.asarray(C, float)
    n, d = V.shape
    triangles_of = [[] for _ in range(n)]
    for t, triangle in enumerate(F):
        for i in triangle:
            triangles_of[i].append(t)
    S = np.zeros((n, d, d))
    for i in range(n):
        for t in triangles_of[i]:
            for k in range(3):
                a, b = F[t, (k + 1) % 3], F[t, (k + 2) % 3]
                S[i] += C[t, k] * np.outer(V[a] - V[b], U[a] - U[b])
    return S
''',
    "arap_rotations": '''import numpy as np


def arap_rotations(V, U, F, C):
    S = arap_covariances(V, U, F, C)
    R = np.empty_like(S)
    for i in range(len(S)):
        u, _, vt = np.linalg.svd(S[i])
        r = vt.T @ u.T
        if np.linalg.det(r) < 0:
            vt[-1] *= -1
            r = vt.T @ u.T
        R[i] = r
    return R
''',
}
LOSES = set()
