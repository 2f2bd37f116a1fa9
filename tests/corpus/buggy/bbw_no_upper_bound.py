NOTEBOOK = "04_bbw"
DESCRIPTION = "bbw() bounds the weights below by 0 but forgets the upper bound 1 (then normalizes)"
SOLUTIONS = {
    "bbw": '''import numpy as np
import scipy.optimize


def bbw(V, F, b, bc):
    Q = biharmonic_matrix(V, F).tocsr()
    b, bc = np.asarray(b), np.asarray(bc, dtype=float)
    free = np.setdiff1d(np.arange(len(V)), b)
    H, G = Q[free][:, free], Q[free][:, b] @ bc
    W = np.clip(unconstrained_biharmonic_weights(V, F, b, bc), 0.0, None)
    for j in range(bc.shape[1]):
        def energy(x):
            Hx = H @ x
            return 0.5 * x @ Hx + G[:, j] @ x, Hx + G[:, j]

        found = scipy.optimize.minimize(
            energy, W[free, j], jac=True, method="L-BFGS-B", bounds=[(0.0, None)] * len(free),
            options={"maxiter": 20000, "maxfun": 40000, "ftol": 1e-15, "gtol": 1e-12, "maxcor": 30},
        )
        W[free, j] = found.x
    return W / W.sum(axis=1, keepdims=True)
''',
}
# Non-negative weights that sum to 1 are <= 1 anyway, so only the biharmonic energy can
# tell: it is off by 0.5-3.5 % depending on the hidden meshes, and the 1 % energy check
# misses it for some seeds (it catches it for the test's seed).
LOSES = {"bbw"}
