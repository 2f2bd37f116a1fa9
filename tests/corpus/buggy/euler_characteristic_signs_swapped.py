NOTEBOOK = "00_meshes"
DESCRIPTION = "euler_characteristic() adds the edges and subtracts the faces: V + E - F"
SOLUTIONS = {
    "euler_characteristic": '''def euler_characteristic(V, F):
    return int(len(V) + len(edges(F)) - len(F))
''',
}
# genus calls euler_characteristic and is judged with the student's own χ: a bug is charged once
LOSES = {"euler_characteristic"}
