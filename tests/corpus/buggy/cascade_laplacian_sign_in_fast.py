import runpy
from pathlib import Path

NOTEBOOK = "06_fast"
DESCRIPTION = "cotangent_laplacian() has the wrong diagonal sign in 06, where only its caller fast_precompute (and what uses it) is graded: they keep their points"
# the same buggy cell as laplacian_diagonal_sign.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("laplacian_diagonal_sign.py")))["SOLUTIONS"]
LOSES = set()
