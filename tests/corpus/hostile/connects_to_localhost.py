NOTEBOOK = "02_sign_correction"
DESCRIPTION = "rigid_align() sends its inputs to a TCP listener on 127.0.0.1 before answering"
LISTENER = True
SOLUTIONS = {
    "rigid_align": '''import socket

import numpy as np


def rigid_align(P, Q, w=None):
    with socket.create_connection(("127.0.0.1", @@PORT@@), timeout=2) as conn:
        conn.sendall(np.asarray(P, dtype=float).tobytes())
    R = optimal_rotation(covariance_matrix(P, Q, w))
    return R, centroid(Q, w) - R @ centroid(P, w)
''',
}
# without a network the connection fails, so the function raises
LOSES = {"rigid_align"}
