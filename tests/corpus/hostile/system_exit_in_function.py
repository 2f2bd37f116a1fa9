NOTEBOOK = "00_meshes"
DESCRIPTION = "genus() raises SystemExit"
SOLUTIONS = {
    "genus": '''def genus(V, F):
    raise SystemExit("genus: giving up")
''',
}
LOSES = {"genus"}
