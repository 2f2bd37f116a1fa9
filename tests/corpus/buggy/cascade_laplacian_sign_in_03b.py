import runpy
from pathlib import Path

NOTEBOOK = "03b_arap_global"
DESCRIPTION = (
    "cotangent_laplacian() has the wrong diagonal sign in 03b, where it is the student's copy of 03's function and "
    "not graded: arap_precompute and what uses it keep their points"
)
# the same buggy cell as laplacian_diagonal_sign.py, copied over into the later stage
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("laplacian_diagonal_sign.py")))["SOLUTIONS"]
LOSES = set()
