import runpy
from pathlib import Path

NOTEBOOK = "04_bbw"
DESCRIPTION = "cotangent_weights() returns cot instead of half cot in 04, where only its callers (biharmonic_matrix and the weights) are graded: they keep their points"
# the same buggy cell as cot_not_halved.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("cot_not_halved.py")))["SOLUTIONS"]
LOSES = set()
