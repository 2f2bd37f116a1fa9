NOTEBOOK = "06_fast"
DESCRIPTION = "fast_energy() drops the constant term (the rest edges' part), so its energies are shifted"
SOLUTIONS = {
    "fast_energy": '''import numpy as np


def fast_energy(data, T, R):
    T_stack = np.asarray(T, dtype=float).transpose(0, 2, 1).reshape(-1, data.d)
    S = data.P @ T_stack
    cross = np.einsum("cij,cji->", np.asarray(R, dtype=float), S)
    return float(np.trace(T_stack.T @ data.Q @ T_stack) - 2.0 * cross)
''',
}
# fast_solve calls fast_energy and is judged with the student's own energies: a bug is charged once
LOSES = {"fast_energy"}
