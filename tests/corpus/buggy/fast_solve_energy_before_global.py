NOTEBOOK = "06_fast"
DESCRIPTION = "fast_solve() records each iteration's energy before its global step (old transforms, new rotations)"
SOLUTIONS = {
    "fast_solve": '''import numpy as np


def fast_solve(data, fixed_transforms, T0=None, iterations=10):
    d, m = data.d, data.m
    T = np.tile(np.eye(d, d + 1), (m, 1, 1)) if T0 is None else np.array(T0, dtype=float)
    T[data.fixed] = fixed_transforms
    energies = []
    for _ in range(iterations):
        R = fast_rotations(data, T)
        energies.append(fast_energy(data, T, R))
        T = fast_global_step(data, R, fixed_transforms)
    return T, np.array(energies)
''',
}
LOSES = {"fast_solve"}
