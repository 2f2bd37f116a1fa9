NOTEBOOK = "00_meshes"
DESCRIPTION = "genus() uses χ = 2 - 2g - b, as if every mesh were connected"
SOLUTIONS = {
    "genus": '''def genus(V, F):
    chi = euler_characteristic(V, F)
    b = boundary_loop_count(F)
    return int((2 - b - chi) // 2)
''',
}
LOSES = {"genus"}
