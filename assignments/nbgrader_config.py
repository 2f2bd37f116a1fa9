# nbgrader course root of the DeformLab `deformation` assignment.
# `deformlab build` writes source/deformation/*.ipynb from ../notebooks and ../reference;
# `deformlab release` runs generate_assignment into release/; `deformlab grade`
# autogrades into autograded/ and this gradebook. formgrader works from this folder as is:
#     cd assignments && jupyter lab   (then open the Formgrader)
from pathlib import Path

c = get_config()  # noqa: F821 - provided by nbgrader when it loads this file

c.CourseDirectory.root = str(Path(__file__).resolve().parent)
c.CourseDirectory.db_url = f"sqlite:///{Path(__file__).resolve().parent / 'gradebook.db'}"
c.CourseDirectory.course_id = "deformlab"
# Grading runs in DeformLab's sandbox (`deformlab grade`); these apply if a TA runs
# `nbgrader autograde` directly instead.
c.ExecutePreprocessor.timeout = 60
c.ClearSolutions.code_stub = {"python": "# YOUR CODE HERE\nraise NotImplementedError()"}
# Where the course kit is (data/, notebooks/) for `deformlab` commands run from this folder,
# also with a non-editable install (pip install ., the Gradescope zip, Dask workers).
c.DeformLab.course_root = ".."
# formgrader shows the TA a model answer and a rubric beside each written answer (cells tagged
# deformlab-ta-only in autograded/); nbgrader's own generate_feedback leaves them out.
try:
    from grader.exports.ta_notes import feedback_preprocessors

    c.GenerateFeedback.preprocessors = feedback_preprocessors()
except ImportError:  # without the kit installed, generate_feedback would return them: use deformlab export
    pass
# The course's assignments: one course pack per folder (grader/course_pack.py reads them).
c.DeformLab.course_packs = ["deformation", "smoothing"]
c.DeformLab.default_assignment = "deformation"
