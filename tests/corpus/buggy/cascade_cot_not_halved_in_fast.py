import runpy
from pathlib import Path

NOTEBOOK = "06_fast"
DESCRIPTION = "cotangent_weights() returns cot instead of half cot in 06, where only its callers (fast_precompute and what uses it) are graded: they keep their points"
# the same buggy cell as cot_not_halved.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("cot_not_halved.py")))["SOLUTIONS"]
LOSES = set()
