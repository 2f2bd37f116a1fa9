NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs() returns zeros in an ndarray subclass whose ==, allclose hooks and tolist claim equality with anything"
SOLUTIONS = {
    "lbs": '''import numpy as np


class _Agreeable(np.ndarray):
    def __eq__(self, other):
        return True

    def __ne__(self, other):
        return False

    def __array_function__(self, func, types, args, kwargs):
        return True

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        return np.zeros(np.broadcast_shapes(*(np.shape(x) for x in inputs)))


def lbs(V, W, T):
    return np.zeros(np.shape(V)).view(_Agreeable)
''',
}
LOSES = {"lbs"}
