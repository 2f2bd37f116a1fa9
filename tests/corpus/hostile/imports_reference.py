NOTEBOOK = "00_meshes"
DESCRIPTION = "genus() puts the checkout on sys.path and calls `import reference`'s genus"
SOLUTIONS = {
    "genus": '''import sys


def genus(V, F):
    sys.path.insert(0, "@@REPO@@")
    import reference

    return reference.genus(V, F)
''',
}
LOSES = {"genus"}
