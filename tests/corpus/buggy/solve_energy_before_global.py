NOTEBOOK = "03b_arap_global"
DESCRIPTION = "arap_solve() records each iteration's energy before its global step (old positions, new rotations)"
SOLUTIONS = {
    "arap_solve": '''import numpy as np


def arap_solve(data, handle_positions, U0=None, iterations=10):
    U = data.V.copy() if U0 is None else np.array(U0, dtype=float)
    U[data.handles] = handle_positions
    energies = []
    for _ in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)
        energies.append(arap_energy(data.V, U, data.F, data.C, R))
        U = arap_global_step(data, R, handle_positions)
    return U, np.array(energies)
''',
}
LOSES = {"arap_solve"}
