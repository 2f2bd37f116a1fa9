import runpy
from pathlib import Path

NOTEBOOK = "04_bbw"
DESCRIPTION = "cotangent_laplacian() has the wrong diagonal sign in 04, where it is not graded: biharmonic_matrix and the unconstrained weights keep their points"
# the same buggy cell as laplacian_diagonal_sign.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("laplacian_diagonal_sign.py")))["SOLUTIONS"]
# biharmonic_matrix is judged with the student's own Laplacian. bbw is not: with +Σ on the diagonal,
# constants leave Q's null space and the bounded weights of vertices far from every handle are all 0,
# so no normalized weights exist to judge (the student's code divides by zero, as any would)
LOSES = {"bbw"}
