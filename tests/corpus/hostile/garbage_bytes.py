NOTEBOOK = "03_arap"
DESCRIPTION = "03_arap.ipynb holds random bytes"
STATUS = "invalid"


def EDIT(nb):
    return bytes((i * 7919 + 13) % 256 for i in range(50_000))


SOLUTIONS = {}
LOSES = {"cotangent_weights", "cotangent_laplacian", "arap_covariances", "arap_rotations", "arap_energy"}
