NOTEBOOK = "01_shape_matching"
DESCRIPTION = "a solution cell writes marker files into the host's /tmp, the checkout, its data/ and starter/"
MUST_NOT_EXIST = (
    "/tmp/deformlab-corpus-@@TOKEN@@-host",
    "@@REPO@@/deformlab-corpus-@@TOKEN@@-repo",
    "@@REPO@@/data/deformlab-corpus-@@TOKEN@@-data",
    "@@REPO@@/starter/deformlab-corpus-@@TOKEN@@-starter.py",
)
SOLUTIONS = {
    "centroid": '''import numpy as np

for _target in (
    "/tmp/deformlab-corpus-@@TOKEN@@-host",
    "@@REPO@@/deformlab-corpus-@@TOKEN@@-repo",
    "@@REPO@@/data/deformlab-corpus-@@TOKEN@@-data",
    "@@REPO@@/starter/deformlab-corpus-@@TOKEN@@-starter.py",
):
    try:
        with open(_target, "w") as _fh:
            _fh.write("escaped the sandbox")
    except OSError:
        pass


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    return (w / w.sum()) @ P
''',
}
LOSES = set()
