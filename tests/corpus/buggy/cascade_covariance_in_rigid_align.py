import runpy
from pathlib import Path

NOTEBOOK = "02_sign_correction"
DESCRIPTION = "covariance_matrix() does not centre the points in 02, where only its caller rigid_align is graded: it keeps its points"
# the same buggy cell as covariance_not_centred.py, copied over into this later stage, where it is not graded
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("covariance_not_centred.py")))["SOLUTIONS"]
LOSES = set()
