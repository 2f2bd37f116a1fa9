NOTEBOOK = "01_shape_matching"
DESCRIPTION = "orthogonal_align() takes t = q̄ - p̄, forgetting that R moves p̄"
SOLUTIONS = {
    "orthogonal_align": '''def orthogonal_align(P, Q, w=None):
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    t = centroid(Q, w) - centroid(P, w)
    return R, t
''',
}
LOSES = {"orthogonal_align"}
