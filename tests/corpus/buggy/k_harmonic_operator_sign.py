from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_operator() builds Q from L instead of -L: negative semi-definite for odd k (Q_1 = L)"
SOLUTIONS = {
    "k_harmonic_operator": teaching_cell(NOTEBOOK, "k_harmonic_operator").replace(
        "minus_L = -sp.csr_matrix(L, dtype=float)", "minus_L = sp.csr_matrix(L, dtype=float)  # the sign of L kept"
    ),
}
LOSES = {"k_harmonic_operator"}
