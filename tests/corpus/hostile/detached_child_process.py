NOTEBOOK = "00_meshes"
DESCRIPTION = "a solution cell starts a sleeping child in its own session, meant to outlive the kernel"
NO_PROCESS = "deformlab-corpus-@@TOKEN@@-child"
SOLUTIONS = {
    "edges": '''import subprocess
import sys

import numpy as np

subprocess.Popen(
    [sys.executable, "-c", "import time; time.sleep(600)", "deformlab-corpus-@@TOKEN@@-child"],
    start_new_session=True,
    stdin=subprocess.DEVNULL,
    stdout=subprocess.DEVNULL,
    stderr=subprocess.DEVNULL,
)


def edges(F):
    F = np.asarray(F)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return np.unique(E, axis=0)
''',
}
LOSES = set()
