NOTEBOOK = "02_sign_correction"
FILENAME = "my notes.ipynb"
STATUS = "missing"
DESCRIPTION = "the only file handed in is a renamed JSON nested 200,000 deep, which the renamed-notebook search must survive"


def EDIT(nb):
    return b"[" * 200_000 + b"]" * 200_000


SOLUTIONS = {}
LOSES = {"optimal_rotation", "rigid_align"}
