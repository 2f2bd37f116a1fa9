import runpy
from pathlib import Path

NOTEBOOK = "06_fast"
DESCRIPTION = "lbs_matrix() applies the weights twice in 06, where only its caller fast_precompute (and what uses it) is graded: they keep their points"
# the same buggy cell as lbs_matrix_weights_squared.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("lbs_matrix_weights_squared.py")))["SOLUTIONS"]
LOSES = set()
