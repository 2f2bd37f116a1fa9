from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_operator() multiplies the factors -L without M⁻¹ between them: (-L)^k, not the k-harmonic energy's matrix"
SOLUTIONS = {
    "k_harmonic_operator": teaching_cell(NOTEBOOK, "k_harmonic_operator").replace(
        "Q = Q @ M_inverse @ minus_L", "Q = Q @ minus_L  # M⁻¹ forgotten"
    ),
}
LOSES = {"k_harmonic_operator"}
