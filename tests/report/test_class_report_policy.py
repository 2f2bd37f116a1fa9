"""The class report lists, per function, the library routines the policy forbids that students' functions called."""

from grader.pipeline.feedback import template
from grader.report.class_report import CSV_TABLES, summarize
from grader.report.scores import policy_lines


def _unit(student: str, notebook: str, tests: list[dict]) -> dict:
    return {"student_id": student, "notebook": notebook, "status": "graded", "score": 0.0, "max_score": 4.0,
            "tests": tests, "reasons": []}


def _test(function: str, violations: list[str]) -> dict:
    return {"function": function, "points": 2.0, "score": 0.0 if violations else 2.0, "summary": "", "cases": [],
            "policy_violations": violations}


RESULTS = [
    _unit("ada", "03_arap", [_test("cotangent_laplacian", ["igl.cotmatrix"]), _test("arap_solve", [])]),
    _unit("bo", "03_arap", [_test("cotangent_laplacian", ["igl.cotmatrix", "igl.arap_solve"]), _test("arap_solve", [])]),
    # a routine the policy allows in that function, and text that is no routine at all, are not counted
    _unit("cy", "05_lbs", [_test("lbs", ["igl.cotmatrix", "<script>alert(1)</script>"]), _test("lbs_matrix", ["igl.lbs_matrix"])]),
]


def test_each_function_and_forbidden_routine_gets_one_row_with_its_students():
    report = summarize(RESULTS)
    assert report.policy == [
        {"notebook": "03_arap", "function": "cotangent_laplacian", "routine": "igl.cotmatrix", "students": 2, "student_ids": "ada bo"},
        {"notebook": "05_lbs", "function": "lbs_matrix", "routine": "igl.lbs_matrix", "students": 1, "student_ids": "cy"},
    ]
    assert "policy" in CSV_TABLES


def test_the_page_shows_the_violations_table():
    page = template("report.html.j2").render(report=summarize(RESULTS), pictures=[], csv_tables=CSV_TABLES, collusion=None, seeds=[1])
    section = page.split('<h2 id="policy">')[1].split("<h2")[0]
    assert "<td>cotangent_laplacian</td><td><code>igl.cotmatrix</code></td>" in section
    assert "alert" not in section


def test_grade_prints_one_line_per_function_and_routine():
    assert policy_lines(RESULTS) == [
        "library policy: cotangent_laplacian called igl.cotmatrix in 2 notebook(s), scored 0",
        "library policy: lbs_matrix called igl.lbs_matrix in 1 notebook(s), scored 0",
    ]
