NOTEBOOK = "01_shape_matching"
DESCRIPTION = (
    "centroid() forks a child that tries unshare(CLONE_NEWUSER | CLONE_NEWNET) (every capability over a network "
    "namespace of its own) and io_uring_setup, the usual first steps of a kernel exploit, and answers wrong if "
    "either works: full marks prove the sandbox refused both"
)
SOLUTIONS = {
    "centroid": '''import ctypes
import os

import numpy as np


def _reached():
    """In a single-threaded child (unshare wants one): which kernel interfaces answered."""
    pid = os.fork()
    if pid == 0:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.syscall.restype = ctypes.c_long
        params = ctypes.create_string_buffer(128)
        user_namespace = libc.unshare(0x10000000 | 0x40000000) == 0
        io_uring = libc.syscall(ctypes.c_long(425), ctypes.c_long(4), ctypes.c_long(ctypes.addressof(params))) >= 0
        os._exit(user_namespace | io_uring << 1)
    return os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    if _reached():
        return np.zeros(P.shape[1])
    return (w / w.sum()) @ P
''',
}
LOSES = set()
