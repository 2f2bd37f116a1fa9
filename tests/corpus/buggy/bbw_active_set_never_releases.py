NOTEBOOK = "04_bbw"
DESCRIPTION = "bbw() runs an active-set loop that holds every value that left [0, 1] at its bound and never releases one"
SOLUTIONS = {
    "bbw": '''import numpy as np
import scipy.sparse.linalg as spla


def bbw(V, F, b, bc):
    b, bc = np.asarray(b, dtype=np.int64), np.asarray(bc, dtype=float)
    Q = biharmonic_matrix(V, F).tocsr()
    free = np.setdiff1d(np.arange(len(V)), b)
    Q_ff = Q[free][:, free].tocsr()
    W = np.zeros((len(V), bc.shape[1]))
    W[b] = bc
    for j in range(bc.shape[1]):
        g = Q[free][:, b] @ bc[:, j]
        at_0 = np.zeros(len(free), dtype=bool)
        at_1 = np.zeros(len(free), dtype=bool)
        while True:
            x = at_1.astype(float)
            inside = ~(at_0 | at_1)
            rhs = -(g[inside] + Q_ff[inside][:, ~inside] @ x[~inside])
            x[inside] = spla.spsolve(Q_ff[inside][:, inside].tocsc(), rhs)
            # hold every value that left [0, 1] at its bound; a held value is never released
            new_0, new_1 = at_0 | (inside & (x < 0)), at_1 | (inside & (x > 1))
            if np.array_equal(new_0, at_0) and np.array_equal(new_1, at_1):
                break
            at_0, at_1 = new_0, new_1
        W[free, j] = np.clip(x, 0.0, 1.0)
    return W / W.sum(axis=1, keepdims=True)
''',
}
LOSES = {"bbw"}
