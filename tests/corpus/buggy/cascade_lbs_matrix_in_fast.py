import runpy
from pathlib import Path

NOTEBOOK = "06_fast"
DESCRIPTION = "lbs_matrix() lays its columns out coordinate by coordinate in 06, where only its caller fast_precompute (and what uses it) is graded: they keep their points"
# the same buggy cell as lbs_matrix_coordinate_major.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("lbs_matrix_coordinate_major.py")))["SOLUTIONS"]
LOSES = set()
