from tests.corpus import teaching_cell

NOTEBOOK = "06_fast"
DESCRIPTION = "fast_precompute() builds Q = Aᵀ(-L)A, forgetting that every edge counts in the cells of its triangle's three corners (Q = 3 Aᵀ(-L)A)"
_TEACHING = teaching_cell(NOTEBOOK, "fast_precompute")
_CORRECT, _BUG = "Q = 3.0 * A.T @", "Q = A.T @"
assert _CORRECT in _TEACHING, "the teaching fast_precompute changed: update this entry"
SOLUTIONS = {"fast_precompute": _TEACHING.replace(_CORRECT, _BUG)}
# fast_rotations only uses the covariance operator P, which is right
LOSES = {"fast_energy", "fast_global_step", "fast_precompute"}
