NOTEBOOK = "05_lbs"
SOURCE = "00_meshes"
DESCRIPTION = "the (correct) 00_meshes notebook handed in as 05_lbs.ipynb"
STATUS = "invalid"
SOLUTIONS = {}
LOSES = {"lbs_matrix", "lbs", "dual_quaternions", "dual_quaternion_transforms", "dqs"}
