import runpy
from pathlib import Path

NOTEBOOK = "03b_arap_global"
DESCRIPTION = (
    "arap_energy() forgets the cotangent weights in 03b, where it is the student's copy of 03's function and not "
    "graded: arap_solve, whose energies it computes, keeps its points"
)
# the same buggy cell as energy_unit_weights.py, copied over into the later stage
SOLUTIONS = runpy.run_path(str(Path(__file__).with_name("energy_unit_weights.py")))["SOLUTIONS"]
LOSES = set()
