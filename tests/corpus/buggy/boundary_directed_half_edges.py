NOTEBOOK = "00_meshes"
DESCRIPTION = "boundary_loop_count() takes the boundary to be the half-edges whose reverse is missing, as if every triangle were oriented alike"
SOLUTIONS = {
    "boundary_loop_count": '''import numpy as np


def boundary_loop_count(F):
    F = np.asarray(F)
    half_edges = {(int(a), int(b)) for a, b in F[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)}
    # a boundary half-edge has no twin; on a boundary loop each vertex starts exactly one of them
    following = {a: b for a, b in half_edges if (b, a) not in half_edges}
    loops = 0
    while following:
        start, vertex = next(iter(following.items()))
        del following[start]
        while vertex != start and vertex in following:
            vertex = following.pop(vertex)
        loops += 1
    return loops
''',
}
# genus() calls the student's boundary_loop_count()
LOSES = {"boundary_loop_count"}
