from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_operator() multiplies k times instead of k - 1: Q_1 comes out as L M⁻¹ L"
SOLUTIONS = {
    "k_harmonic_operator": teaching_cell(NOTEBOOK, "k_harmonic_operator").replace("for _ in range(k - 1):", "for _ in range(k):"),
}
LOSES = {"k_harmonic_operator"}
