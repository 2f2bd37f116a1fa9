NOTEBOOK = "04_bbw"
DESCRIPTION = "bbw() clips the unconstrained biharmonic weights to [0, 1] and normalizes, instead of solving the bounded problem"
SOLUTIONS = {
    "bbw": '''import numpy as np


def bbw(V, F, b, bc):
    W = np.clip(unconstrained_biharmonic_weights(V, F, b, bc), 0.0, 1.0)
    return W / W.sum(axis=1, keepdims=True)
''',
}
LOSES = {"bbw"}
