import nbformat

NOTEBOOK = "01_shape_matching"
DESCRIPTION = "an added cell displays 2,000 outputs of 100 kB each (200 MB in one cell, each output under the per-output cap)"
_FLOOD = '''from IPython.display import display

for _i in range(2000):
    display({"text/plain": f"{_i:05d}" + "x" * 100_000}, raw=True)
'''


def EDIT(nb):
    nb.cells.append(nbformat.v4.new_code_cell(_FLOOD))
    return nb


def CHECK(result, autograded, params):
    size = len(autograded or "")
    return [] if size < 4 * 2**20 else [f"the executed notebook kept {size / 2**20:.0f} MiB of outputs"]


SOLUTIONS = {}
LOSES = set()
