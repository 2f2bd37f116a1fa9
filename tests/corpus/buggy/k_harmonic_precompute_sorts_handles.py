from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = (
    "k_harmonic_precompute() keeps np.unique(handles), which also sorts them: the displacements then go to the "
    "wrong handles unless the caller gave them in ascending order"
)
SOLUTIONS = {
    "k_harmonic_precompute": teaching_cell(NOTEBOOK, "k_harmonic_precompute").replace(
        "    free = np.setdiff1d(np.arange(n), handles)\n",
        "    handles = np.unique(handles)  # tidy: each once, in order\n    free = np.setdiff1d(np.arange(n), handles)\n",
    ),
}
# every hidden problem gives its handles in random order; the solve takes the student's precompute object
LOSES = {"k_harmonic_precompute", "k_harmonic_solve"}
