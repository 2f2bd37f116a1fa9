"""`deformlab release` builds the handouts and proves them sound (slow: it executes every notebook)."""

import zipfile
from pathlib import Path

import nbformat
import pytest

from grader.course_pack import pack

from grader.build.authored import solution_body
from grader.build.release import (
    ReleaseReport,
    check_demo_execution,
    public_lines,
    reference_body,
    release,
    scan_for_leaks,
    teaching_bodies,
    write_bundle,
)
from grader.paths import CoursePaths
from tests.course_copy import copy_course_config

ROOT = Path(__file__).resolve().parents[2]
DEMO = "demo_skinning"


@pytest.fixture(scope="module")
def released(tmp_path_factory):
    """A release of this checkout's notebooks and reference, made in a temporary course."""
    root = tmp_path_factory.mktemp("course")
    for name in ("notebooks", "starter", "data", "reference"):
        (root / name).symlink_to(ROOT / name)
    copy_course_config(root / "assignments")
    paths = CoursePaths(root)
    return paths, release(paths=paths)


@pytest.mark.slow
def test_the_release_passes_every_check(released):
    paths, report = released
    assert report.problems == []
    assert set(report.points) == {"00_meshes", "01_shape_matching", "02_sign_correction", "02b_k_harmonic", "03_arap", "03b_arap_global", "04_bbw", "05_lbs", "06_fast", "07_tetrahedra"}
    assert all(p > 0 for p in report.points.values())


@pytest.mark.slow
def test_release_notebooks_keep_signatures_and_docstrings_but_no_solution(released):
    paths, _ = released
    nb = nbformat.read(paths.release / "deformation" / "03b_arap_global.ipynb", as_version=4)
    cell = next(c for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("grade_id") == "solution_arap_solve")
    assert cell.source.count("def arap_solve(") == 1
    assert '"""' in cell.source and "raise NotImplementedError()" in cell.source
    source = nbformat.read(paths.source / "deformation" / "03b_arap_global.ipynb", as_version=4)
    taught = next(c for c in source.cells if (c.metadata.get("nbgrader") or {}).get("grade_id") == "solution_arap_solve")
    body = [line.strip() for line in solution_body(taught.source).splitlines() if len(line.strip()) > 20]
    assert body and not any(line in cell.source for line in body)


@pytest.mark.slow
def test_the_student_bundle_has_what_students_need_and_nothing_else(released):
    paths, _ = released
    with zipfile.ZipFile(paths.dist / "deformation-student.zip") as z:
        names = set(z.namelist())
    for needed in ("deformation/03_arap.ipynb", "deformation/03b_arap_global.ipynb", "deformation/starter/plotting.py", "deformation/data/bar.npz",
                   "deformation/requirements.txt", "deformation/README.md", "deformation/check_notebook.py"):
        assert needed in names
    assert not any("/reference/" in n or "/grader/" in n or n.endswith("gradebook.db") for n in names)


@pytest.mark.slow
def test_the_release_bundles_the_demo_and_runs_it(released):
    paths, report = released
    with zipfile.ZipFile(paths.dist / "deformation-student.zip") as z:
        assert f"deformation/{DEMO}.ipynb" in z.namelist()
    assert f"demo {DEMO}" in report.timings, report.timings


def test_the_bundle_ships_the_demo_without_outputs_next_to_starter_with_its_requirements(tmp_path):
    import jupytext

    for name in ("notebooks", "starter", "data"):
        (tmp_path / name).symlink_to(ROOT / name)
    paths = CoursePaths(tmp_path)
    (paths.release / "deformation").mkdir(parents=True)
    with zipfile.ZipFile(write_bundle(paths, "deformation")) as z:
        names = set(z.namelist())
        nb = nbformat.reads(z.read(f"deformation/{DEMO}.ipynb").decode(), as_version=4)
        requirements = z.read("deformation/requirements.txt").decode()
        readme = z.read("deformation/README.md").decode()
    assert {"deformation/starter/skinning_widget.py", "deformation/starter/posing.py", "deformation/data/character_fine.npz"} <= names
    authored = jupytext.read(ROOT / "notebooks" / "demo_skinning" / "demo_skinning.py")
    assert [(c.cell_type, c.source) for c in nb.cells] == [(c.cell_type, c.source) for c in authored.cells]
    assert all(not c.get("outputs") and "nbgrader" not in c.metadata for c in nb.cells)
    assert "deformlab" not in nb.metadata and nb.metadata["kernelspec"]["name"] == "python3"
    assert scan_for_leaks({f"{DEMO}.ipynb": nbformat.writes(nb)}) == []
    assert "ipywidgets" in requirements and f"{DEMO}.ipynb" in readme
    assert "LIBRARY_POLICY.md" in readme and "deformation/LIBRARY_POLICY.md" in names


def test_the_demo_check_reports_a_failing_cell_and_missing_widget_and_animation(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    broken = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("open('posed.gif', 'wb').close()"), nbformat.v4.new_code_cell("1 / 0")])
    broken.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    report = ReleaseReport()
    check_demo_execution(broken, report, DEMO)
    assert report.problems == [
        f"demo {DEMO}.ipynb, cell 2 fails: ZeroDivisionError: division by zero",
        f"demo {DEMO}.ipynb does not show the widget (application/vnd.jupyter.widget-view+json)",
        f"demo {DEMO}.ipynb does not show the animation (image/gif)",
    ]
    assert f"demo {DEMO}" in report.timings
    assert list(tmp_path.iterdir()) == [], "the demo must run in a scratch folder, not where it is called from"


def test_the_leak_scan_finds_a_pasted_reference_body():
    import json

    pasted = {"cells": [{"source": ["x = 1\n"] + [line + "\n" for line in reference_body("optimal_rotation").splitlines()]}]}
    problems = scan_for_leaks({"release/02.ipynb": json.dumps(pasted)})
    assert any("the code of reference optimal_rotation" in p for p in problems)


def test_the_leak_scan_finds_a_pasted_teaching_solution():
    teaching = teaching_bodies("deformation")
    assert "teaching arap_solve (03b_arap_global)" in teaching
    pasted = "def f():\n" + "\n".join("    " + line for line in teaching["teaching arap_solve (03b_arap_global)"].splitlines())
    problems = scan_for_leaks({"starter/helper.py": pasted}, teaching)
    assert any("the code of teaching arap_solve (03b_arap_global)" in p for p in problems)


def test_the_leak_scan_ignores_public_input_checks():
    assert scan_for_leaks({"starter/x.py": 'U = as_float_array(U, "U", ndim=2)\nV = as_vertices(V)\n'}) == []


def test_the_leak_scan_finds_hidden_test_markers():
    problems = scan_for_leaks({"release/02.ipynb": "### BEGIN HIDDEN TESTS\nfrom grader.checks import x"})
    assert any("BEGIN HIDDEN TESTS" in p for p in problems)
    assert any("grader.checks" in p for p in problems)


def test_the_bundles_readme_names_every_notebook_its_files_are_readable_and_its_requirements_pinned(tmp_path):
    for name in ("notebooks", "starter", "data", "constraints.txt"):
        (tmp_path / name).symlink_to(ROOT / name)
    paths = CoursePaths(tmp_path)
    (paths.release / "deformation").mkdir(parents=True)
    with zipfile.ZipFile(write_bundle(paths, "deformation")) as z:
        modes = {i.filename: (i.external_attr >> 16) & 0o777 for i in z.infolist()}
        requirements = z.read("deformation/requirements.txt").decode()
        readme = z.read("deformation/README.md").decode()
    assert {name for name, mode in modes.items() if mode & 0o044 != 0o044} == set(), "every file readable by group and others"
    stages = pack("deformation").stage_names
    first = readme.split("\n\n")[1]
    assert first.split()[0] == "Ten" and len(stages) == 10 and all(f"`{s}`" in first for s in stages)
    pins = dict(line.split("==") for line in (ROOT / "constraints.txt").read_text().splitlines()
                if "==" in line and not line.startswith("#"))
    wanted = dict(line.split("==") for line in requirements.splitlines() if not line.startswith("#"))
    assert wanted and all(">" not in v for v in wanted.values())
    assert {n: v for n, v in wanted.items() if n in pins} == {n: pins[n] for n in wanted if n in pins}
    assert {"numpy", "scipy", "libigl", "pyvista"} <= set(pins) & set(wanted)


def _notebook(*cells) -> str:
    return nbformat.writes(nbformat.v4.new_notebook(cells=list(cells)))


def test_the_leak_scan_refuses_one_line_of_a_reference_body_in_a_provided_cell():
    provided = nbformat.v4.new_code_cell(
        "import numpy as np\n\n\ndef ratio(dot, double_area):\n    return 0.5 * dot / double_area[:, None]\n"
    )
    problems = scan_for_leaks({"release/03_arap.ipynb": _notebook(provided)}, public=public_lines(CoursePaths(ROOT)))
    assert problems == [
        "release/03_arap.ipynb contains the code of reference cotangent_weights: 'return 0.5 * dot / double_area[:, None]' (1 lines)"
    ]


def test_the_leak_scan_refuses_a_markdown_hint_quoting_the_sign_fix():
    teaching = teaching_bodies("deformation")
    for quote, body in (
        ("U_svd[..., -1]  *=  sign[..., None]", "teaching optimal_rotation (02_sign_correction)"),  # spacing changed
        ("Vt[np.linalg.det(U @ Vt) < 0, -1, :] *= -1.0", "reference optimal_rotation"),
    ):
        hint = nbformat.v4.new_markdown_cell(f"**Hint.** Flip the last singular vector where needed: `{quote}` does it.")
        problems = scan_for_leaks({"release/02_sign_correction.ipynb": _notebook(hint)}, teaching, public_lines(CoursePaths(ROOT)))
        assert any(p.startswith(f"release/02_sign_correction.ipynb contains the code of {body}: ") for p in problems), problems


def test_the_leak_scan_ignores_lines_public_code_also_has():
    shared = "W = weights(V)\nreturn W / W.sum(axis=1, keepdims=True)\n"  # row normalization, also in starter/
    assert "return W / W.sum(axis=1, keepdims=True)" in public_lines(CoursePaths(ROOT))
    assert scan_for_leaks({"release/04_bbw.ipynb": shared}, public=public_lines(CoursePaths(ROOT))) == []
    assert scan_for_leaks({"release/04_bbw.ipynb": shared}) != [], "without the public lines the same line is a leak"


def test_the_leak_scan_ignores_a_call_of_a_contract_function_and_comments():
    text = "data = arap_precompute(V, F, handles)\n# U = arap_global_step(data, R, handle_positions) and so on\n"
    assert scan_for_leaks({"release/03_arap.ipynb": text}) == []
