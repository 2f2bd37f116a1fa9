NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_mass_matrix() spreads the signed volumes: negatively oriented tetrahedra take mass away"
SOLUTIONS = {
    "tet_mass_matrix": '''import numpy as np
import scipy.sparse as sp


def tet_mass_matrix(V, T):
    T = np.asarray(T)
    quarter = tet_volumes(V, T) / 4
    return sp.diags(np.bincount(T.ravel(), weights=np.repeat(quarter, 4), minlength=len(V)))
''',
}
# tet_biharmonic_matrix calls it and is judged with the student's own masses: a bug is charged once
LOSES = {"tet_mass_matrix"}
