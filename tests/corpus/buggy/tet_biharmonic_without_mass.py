NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_biharmonic_matrix() returns L L, without the mass matrix's inverse between the Laplacians"
SOLUTIONS = {
    "tet_biharmonic_matrix": '''import scipy.sparse as sp


def tet_biharmonic_matrix(V, T):
    L = sp.csr_matrix(tet_cotangent_laplacian(V, T))
    return L @ L
''',
}
LOSES = {"tet_biharmonic_matrix"}
