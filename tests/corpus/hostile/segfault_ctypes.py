NOTEBOOK = "05_lbs"
STATUS = "graded-with-incidents"
DESCRIPTION = "lbs_matrix() reads memory at address 8 through ctypes: a segmentation fault kills the kernel"
SOLUTIONS = {
    "lbs_matrix": '''import ctypes


def lbs_matrix(V, W):
    return ctypes.c_int.from_address(8).value
''',
}
LOSES = {"lbs_matrix"}
