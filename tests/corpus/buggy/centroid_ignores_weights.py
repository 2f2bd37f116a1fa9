NOTEBOOK = "01_shape_matching"
DESCRIPTION = "centroid() takes the plain mean even when weights are given"
SOLUTIONS = {
    "centroid": '''import numpy as np


def centroid(P, w=None):
    return np.asarray(P, dtype=float).mean(axis=0)
''',
}
# the weighted covariance and the alignment use the centroid
LOSES = {"centroid"}
