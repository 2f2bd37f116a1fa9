from tests.corpus import teaching_cell

NOTEBOOK = "02b_k_harmonic"
DESCRIPTION = "k_harmonic_precompute() never checks handles: an empty, repeated or out-of-range handle gets a crash or a meaningless system instead of the contract's ValueError"
CHECKS = """    if handles.ndim != 1 or len(handles) == 0:
        raise ValueError("handles must list at least one vertex")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handles must be vertices 0..{n - 1}")
    if len(np.unique(handles)) < len(handles):
        raise ValueError("handles repeats a vertex")
"""
SOLUTIONS = {
    "k_harmonic_precompute": teaching_cell(NOTEBOOK, "k_harmonic_precompute").replace(CHECKS, ""),
}
LOSES = {"k_harmonic_precompute"}
