NOTEBOOK = "01_shape_matching"
DESCRIPTION = "a correct centroid() that prints debugging to stderr and triggers a numpy RuntimeWarning (stock nbgrader zeroes such tests)"
SOLUTIONS = {
    "centroid": '''import sys
import warnings

import numpy as np


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    print(f"debug: centroid of {len(P)} points", file=sys.stderr)
    np.log(np.zeros(1))  # RuntimeWarning: divide by zero, harmless here
    warnings.warn("a student's own warning")
    return (w / w.sum()) @ P
''',
}
LOSES = set()
