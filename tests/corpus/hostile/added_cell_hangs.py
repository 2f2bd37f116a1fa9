import nbformat

NOTEBOOK = "05_lbs"
STATUS = "graded-with-incidents"
DESCRIPTION = "an added cell after the solutions sleeps forever (no contract call, so it runs when grading)"


def EDIT(nb):
    nb.cells.append(nbformat.v4.new_code_cell("import time\n\nwhile True:\n    time.sleep(1)\n"))
    return nb


SOLUTIONS = {}
# the kernel is killed at the timeout and restarted; every definition came before
LOSES = set()
