import runpy
from pathlib import Path

NOTEBOOK = "02_sign_correction"
DESCRIPTION = "centroid() ignores the weights in 02, where only its callers (rigid_align) are graded: they keep their points"
# the same buggy cell as centroid_ignores_weights.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("centroid_ignores_weights.py")))["SOLUTIONS"]
LOSES = set()
