NOTEBOOK = "04_bbw"
DESCRIPTION = "biharmonic_matrix() drops the mass matrix: Q = L L instead of L M⁻¹ L"
SOLUTIONS = {
    "biharmonic_matrix": '''import scipy.sparse as sp


def biharmonic_matrix(V, F):
    L = sp.csc_matrix(cotangent_laplacian(V, F))
    return (L @ L).tocsc()
''',
}
# both weight solvers minimize wᵀ Q w
LOSES = {"biharmonic_matrix"}
