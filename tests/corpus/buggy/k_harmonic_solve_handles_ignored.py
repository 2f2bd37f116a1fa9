from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_solve() solves Q_ff D_f = 0: the handles' columns never reach the right-hand side, the free vertices stay put"
SOLUTIONS = {
    "k_harmonic_solve": teaching_cell(NOTEBOOK, "k_harmonic_solve").replace(
        'b = -(data["Q_fh"] @ D_h)', 'b = np.zeros((len(data["free"]), D_h.shape[1]))'
    ),
}
LOSES = {"k_harmonic_solve", "k_harmonic_precompute"}
