NOTEBOOK = "05_lbs"
DESCRIPTION = "dqs() blends the dual quaternions as dual_quaternions() returns them, never flipping one to handle 0's side"
SOLUTIONS = {
    "dqs": '''import numpy as np


def dqs(V, W, T):
    V, W = np.asarray(V, float), np.asarray(W, float)
    Q = dual_quaternions(T)
    blends = (W @ Q.reshape(len(Q), 8)).reshape(len(V), 2, 4)
    T_blend = dual_quaternion_transforms(blends)
    return np.einsum("iab,ib->ia", T_blend[:, :, :3], V) + T_blend[:, :, 3]
''',
}
LOSES = {"dqs"}
