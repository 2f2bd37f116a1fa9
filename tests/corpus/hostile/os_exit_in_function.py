NOTEBOOK = "01_shape_matching"
STATUS = "graded-with-incidents"
DESCRIPTION = "orthogonal_align() calls os._exit(1): the kernel dies while its outputs are collected"
SOLUTIONS = {
    "orthogonal_align": '''import os


def orthogonal_align(P, Q, w=None):
    os._exit(1)
''',
}
LOSES = {"orthogonal_align"}
