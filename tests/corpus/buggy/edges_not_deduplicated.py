NOTEBOOK = "00_meshes"
DESCRIPTION = "edges() sorts each triangle side but keeps both half-edges of every interior edge"
SOLUTIONS = {
    "edges": '''import numpy as np


def edges(F):
    F = np.asarray(F)
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E = np.sort(E, axis=1)
    return E[np.lexsort((E[:, 1], E[:, 0]))]
''',
}
# euler_characteristic is judged with the student's own edges(); genus loses too: with the
# duplicated edges χ is no orientable manifold's, where the contract's genus raises, so no rerun applies
LOSES = {"edges", "genus"}
