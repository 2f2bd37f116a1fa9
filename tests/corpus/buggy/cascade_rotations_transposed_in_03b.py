import runpy
from pathlib import Path

NOTEBOOK = "03b_arap_global"
DESCRIPTION = (
    "arap_rotations() returns each R_i transposed in 03b, where it is the student's copy of 03's function and not "
    "graded: arap_solve, which calls it, keeps its points"
)
# the same buggy cell as arap_rotations_transposed.py, copied over into the later stage
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("arap_rotations_transposed.py")))["SOLUTIONS"]
LOSES = set()
