NOTEBOOK = "02_sign_correction"
DESCRIPTION = "optimal_rotation() opens the checkout's reference/sign_correction.py by absolute path and runs its code"
SOLUTIONS = {
    "optimal_rotation": '''def optimal_rotation(S):
    namespace = {}
    with open("@@REPO@@/reference/sign_correction.py") as fh:
        source = fh.read()
    exec(compile(source, "sign_correction.py", "exec"), namespace)
    return namespace["optimal_rotation"](S)
''',
}
LOSES = {"optimal_rotation", "rigid_align"}
