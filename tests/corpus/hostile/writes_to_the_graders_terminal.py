NOTEBOOK = "01_shape_matching"
DESCRIPTION = (
    "centroid() looks through its own descriptors and those of the sandbox's pid 1 for one that leads out of the "
    "sandbox (a terminal, or a file that is not the one its path names inside: the grader's stdout, stderr or log) "
    "and answers wrong if it finds one: it could write escape sequences to the TA's terminal there. Full marks "
    "prove the sandbox holds none"
)
SOLUTIONS = {
    "centroid": '''import os
import stat

import numpy as np

# the character devices bubblewrap's /dev holds: null, zero, full, random, urandom, tty
_SANDBOX_DEVICES = {(1, 3), (1, 5), (1, 7), (1, 8), (1, 9), (5, 0)}


def _leads_out(link):
    """A terminal, or a file that is not the one its path names in here (gone, or outside the sandbox)."""
    try:
        st = os.stat(link)
        path = os.readlink(link)
    except OSError:  # gone, or not ours to look at
        return False
    if stat.S_ISCHR(st.st_mode):
        return (os.major(st.st_rdev), os.minor(st.st_rdev)) not in _SANDBOX_DEVICES
    if not stat.S_ISREG(st.st_mode):
        return False
    try:
        here = os.stat(path)
    except OSError:
        return True
    return (here.st_dev, here.st_ino) != (st.st_dev, st.st_ino)


def _reached():
    for pid in ("self", "1"):
        try:
            descriptors = os.listdir(f"/proc/{pid}/fd")
        except OSError:
            continue
        if any(_leads_out(f"/proc/{pid}/fd/{fd}") for fd in descriptors):
            return True
    return False


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    if _reached():
        return np.zeros(P.shape[1])
    return (w / w.sum()) @ P
''',
}
LOSES = set()
