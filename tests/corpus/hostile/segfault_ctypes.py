NOTEBOOK = "05_lbs"
DESCRIPTION = "lbs_matrix() reads address 0 through ctypes: a segmentation fault in the kernel"
SOLUTIONS = {
    "lbs_matrix": '''import ctypes


def lbs_matrix(V, W):
    return ctypes.string_at(0, 64)
''',
}
LOSES = {"lbs_matrix"}
