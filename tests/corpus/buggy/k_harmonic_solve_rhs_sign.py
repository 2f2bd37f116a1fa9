from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_solve() solves Q_ff D_f = +Q_fh D_h (the minus sign of the right-hand side dropped)"
SOLUTIONS = {
    "k_harmonic_solve": teaching_cell(NOTEBOOK, "k_harmonic_solve").replace('b = -(data["Q_fh"] @ D_h)', 'b = data["Q_fh"] @ D_h'),
}
# the precomputation is graded through the student's own solve: the two share their points
LOSES = {"k_harmonic_solve", "k_harmonic_precompute"}
