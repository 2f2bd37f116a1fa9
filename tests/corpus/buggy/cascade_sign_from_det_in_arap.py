import runpy
from pathlib import Path

NOTEBOOK = "03_arap"
DESCRIPTION = "optimal_rotation() takes its sign from det(S) in 03, where only its caller arap_rotations is graded: it keeps its points"
# the same buggy cell as sign_from_det_of_s.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("sign_from_det_of_s.py")))["SOLUTIONS"]
LOSES = set()
