import re

import nbformat

NOTEBOOK = "02_sign_correction"
DESCRIPTION = "an added cell fallocates 64 files of 256 MiB (16 GiB) in its working folder and prints how much it got"
_FILL = '''import os

_total = 0
for _i in range(64):
    try:
        with open(f"fill-{_i}.bin", "wb") as _fh:
            os.posix_fallocate(_fh.fileno(), 0, 256 * 2**20)
        _total += 256 * 2**20
    except OSError:
        break
print("ALLOCATED", _total)
'''


def EDIT(nb):
    nb.cells.append(nbformat.v4.new_code_cell(_FILL))
    return nb


def CHECK(result, autograded, params):
    found = re.search(r"ALLOCATED (\d+)", autograded or "")
    if found is None:
        return ["the filling cell printed nothing"]
    cap = int(params["DISK_BYTES"])
    return [] if int(found.group(1)) <= cap else [f"the submission allocated {found.group(1)} bytes, over its {cap}-byte workdir"]


SOLUTIONS = {}
LOSES = set()
