NOTEBOOK = "06_fast"
DESCRIPTION = "fast_solve() starts from T0 as given, without putting the fixed transforms into its fixed rows first"
SOLUTIONS = {
    "fast_solve": '''import numpy as np


def fast_solve(data, fixed_transforms, T0=None, iterations=10):
    d, m = data.d, data.m
    if T0 is None:
        T = np.tile(np.eye(d, d + 1), (m, 1, 1))
        T[data.fixed] = fixed_transforms
    else:
        T = np.array(T0, dtype=float)
    energies = []
    for _ in range(iterations):
        R = fast_rotations(data, T)
        T = fast_global_step(data, R, fixed_transforms)
        energies.append(fast_energy(data, T, R))
    return T, np.array(energies)
''',
}
LOSES = {"fast_solve"}
