NOTEBOOK = "05_lbs"
DESCRIPTION = "dual_quaternions() reads w = √(1 + tr R)/2 and divides the other components by 4w: half turns (w = 0) give NaN"
SOLUTIONS = {
    "dual_quaternions": '''import numpy as np


def dual_quaternions(T):
    T = np.asarray(T, dtype=float)
    Q = np.zeros((len(T), 2, 4))
    for j, (R, t) in enumerate(zip(T[:, :, :3], T[:, :, 3])):
        w = np.sqrt(max(1.0 + np.trace(R), 0.0)) / 2
        v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (4 * w)
        Q[j, 0] = np.r_[w, v]
        Q[j, 1] = 0.5 * np.r_[-t @ v, w * t + np.cross(t, v)]
    return Q
''',
}
LOSES = {"dual_quaternions"}
