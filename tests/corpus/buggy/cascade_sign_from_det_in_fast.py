import runpy
from pathlib import Path

NOTEBOOK = "06_fast"
DESCRIPTION = "optimal_rotation() takes its sign from det(S) in 06, where only its caller fast_rotations (and fast_solve) are graded: they keep their points"
# the same buggy cell as sign_from_det_of_s.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("sign_from_det_of_s.py")))["SOLUTIONS"]
LOSES = set()
