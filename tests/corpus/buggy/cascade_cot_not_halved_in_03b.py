import runpy
from pathlib import Path

NOTEBOOK = "03b_arap_global"
DESCRIPTION = (
    "cotangent_weights() returns cot instead of half cot in 03b, where it is the student's copy of 03's function and "
    "not graded: arap_precompute and what uses it keep their points"
)
# the same buggy cell as cot_not_halved.py, copied over into the later stage
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("cot_not_halved.py")))["SOLUTIONS"]
LOSES = set()
