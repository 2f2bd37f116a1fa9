NOTEBOOK = "00_meshes"
DESCRIPTION = "the first call of edges() forks children until the sandbox refuses (at most 2000), reaps them, then answers"
NEEDS_PROCESS_CAP = True
EVENT = "the sandbox refused"
SOLUTIONS = {
    "edges": '''import os
import time

import numpy as np


STORMED = []


def edges(F):
    children = []
    while not STORMED and len(children) < 2000:
        try:
            pid = os.fork()
        except BlockingIOError:
            STORMED.append(len(children))
            break
        if pid == 0:
            time.sleep(0.2)
            os._exit(0)
        children.append(pid)
    for pid in children:
        os.waitpid(pid, 0)
    F = np.asarray(F)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return np.unique(E, axis=0)
''',
}
LOSES = set()
