"""The hidden reference solution: every function of the student contract.

One module per stage; every contract function is importable from the package
itself, e.g. ``from reference import arap_solve``.
"""
