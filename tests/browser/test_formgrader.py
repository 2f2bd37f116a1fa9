"""formgrader in headless Chromium: a TA opening an attacker's submission leaves the gradebook as it was.

A private course (its own ``assignments/`` with the checkout's ``nbgrader_config.py``, gradebook and
``autograded/``) grades an honest student and one attacker per active-content corpus entry with
``grade_class``; formgrader (nbgrader's server extension in ``jupyter server``, started in the
course folder as a TA would) serves it on 127.0.0.1. The TA opens each attacker's submission page;
no script of the student's may run: no dialog, and every grade, manual score and extra credit in the
gradebook is unchanged; the page shows each cell's points as the instructor set them. The positive control puts the same attacker's notebook executed *without*
``neutralize`` where formgrader reads it: the same page then runs the student's scripts, which give
that submission full manual marks plus extra credit, so this test can fail.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import nbformat
import pytest
from tests.course_copy import copy_course_config

from tests.corpus import build_submission, load_entry, student_id, student_notebook
from grader.paths import CoursePaths

from .conftest import CHROMIUM, NO_CHROMIUM, jupyter_env, jupyter_server

if not CHROMIUM.is_file():
    pytest.skip(NO_CHROMIUM, allow_module_level=True)
pytest.importorskip("playwright.sync_api", reason="the playwright package (the dev extra) is not installed")

pytestmark = [pytest.mark.slow, pytest.mark.timeout(300)]

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = "00_meshes"  # the quickest notebook with a short answer graded by hand
HOSTILE = ROOT / "tests" / "corpus" / "hostile"
ATTACKS = ["displays_script_in_definition_cell", "displays_svg_widget_and_fake_png", "markdown_answer_with_html",
           "cell_metadata_injects_html"]
HONEST = "honest_student"
#: A student whose ``edges`` raises an error with markup in its message: formgrader must show it as text.
MARKUP = "markup_in_error"
MARKUP_EDGES = 'def edges(F):\n    raise ValueError("<img src=x onerror=alert(\'deformlab-attack:verdict\')> not done")\n'
SEED = 20240611
SETTLE_S = 1.0  # after the page is idle (no request for 0.5 s); the control's scripts have reported by then


@dataclass
class Course:
    paths: CoursePaths
    submitted: Path
    results: dict[str, dict]

    @property
    def db_url(self) -> str:
        return self.paths.gradebook_url

    def autograded(self, sid: str) -> Path:
        return self.paths.course / "autograded" / sid / "deformation" / f"{NOTEBOOK}.ipynb"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("formgrader")


@pytest.fixture(scope="module")
def course(workdir, source_notebooks):
    """The class graded into a private copy of the course, as ``deformlab grade`` does it."""
    from grader.pipeline.run import GradeOptions, grade_class

    paths = CoursePaths(workdir / "course")
    (paths.source / "deformation").mkdir(parents=True)
    for name in ("data", "starter", "notebooks"):
        (paths.root / name).symlink_to(ROOT / name)
    copy_course_config(paths.course)
    shutil.copy(source_notebooks[NOTEBOOK], paths.source / "deformation")
    submitted = workdir / "submitted"
    source = paths.source / "deformation"
    for name in ATTACKS:
        entry = load_entry(HOSTILE / f"{name}.py")
        build_submission(entry, source, submitted, student_id(entry), {"REPO": str(ROOT), "PORT": "1", "TOKEN": "t"})
    honest = submitted / HONEST / "deformation" / f"{NOTEBOOK}.ipynb"
    honest.parent.mkdir(parents=True)
    nbformat.write(student_notebook(nbformat.read(source_notebooks[NOTEBOOK], as_version=4), {}), honest)
    markup = submitted / MARKUP / "deformation" / f"{NOTEBOOK}.ipynb"
    markup.parent.mkdir(parents=True)
    nbformat.write(student_notebook(nbformat.read(source_notebooks[NOTEBOOK], as_version=4), {"edges": MARKUP_EDGES}), markup)
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("DEFORMLAB_ROOT", str(paths.root))
        # nbgrader's Gradebook runs the `alembic` script of this environment
        mp.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
        results = grade_class(submitted, workdir / "out", GradeOptions(workers=2, timeout=10, seed=SEED, progress=False),
                              paths)
    return Course(paths, submitted, {r["student_id"]: r for r in results})


@pytest.fixture(scope="module")
def formgrader(workdir, course):
    """``jupyter server`` with nbgrader's formgrader, run from the course folder (where nbgrader_config.py is)."""
    env = jupyter_env(workdir)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
    args = ["--ServerApp.jpserver_extensions=nbgrader.server_extensions.formgrader=True"]
    with jupyter_server("server", course.paths.course, workdir / "formgrader.log", env, args) as server:
        yield server


def gradebook(db_url: str) -> dict:
    """Every grade and comment of every submitted notebook: ``{(student, notebook, cell): (...)}``."""
    from nbgrader.api import Gradebook

    with Gradebook(db_url) as gb:
        return {
            (nb.student.id, nb.name, grade.name): (grade.auto_score, grade.manual_score, grade.extra_credit,
                                                   grade.needs_manual_grade)
            for assignment in gb.assignments for nb in gb.notebook_submissions(NOTEBOOK, assignment.name)
            for grade in nb.grades
        } | {
            (nb.student.id, nb.name, f"comment {c.name}"): (c.auto_comment, c.manual_comment)
            for assignment in gb.assignments for nb in gb.notebook_submissions(NOTEBOOK, assignment.name)
            for c in nb.comments
        }


def submission_id(db_url: str, sid: str) -> str:
    from nbgrader.api import Gradebook

    with Gradebook(db_url) as gb:
        return gb.find_submission_notebook(NOTEBOOK, "deformation", sid).id


def log_in(browser, server) -> None:
    """Log the browser in as the TA with the server's token, through the login form (a session cookie)."""
    page = browser.new_page()
    page.goto(f"{server.url}/login")
    if page.locator("input[name=password]").count() == 0:  # logged in by an earlier test: the session cookie holds
        page.close()
        return
    page.fill("input[name=password]", server.token)
    with page.expect_navigation():
        page.press("input[name=password]", "Enter")
    page.close()


def open_as_ta(browser, server, db_url: str, sid: str, shots: Path, tag: str) -> tuple[list[str], list[float], Path]:
    """Open ``sid``'s submission in formgrader and wait until it is shown and idle.

    Returns
    -------
    (list of str, list of float, Path)
        The messages of the dialogs the page opened, the points shown beside each score box, and a screenshot.
    """
    page = browser.new_page()
    dialogs: list[str] = []
    page.on("dialog", lambda dialog: (dialogs.append(dialog.message), dialog.dismiss()))
    answer = page.goto(f"{server.url}/formgrader/submissions/{submission_id(db_url, sid)}/?index=0")
    assert answer is not None and answer.status == 200, f"formgrader answered {answer and answer.status}:\n{server.log_tail()}"
    page.wait_for_load_state("networkidle")
    page.wait_for_timeout(SETTLE_S * 1000)
    shot = shots / f"{sid}-{tag}.png"
    page.screenshot(path=str(shot), full_page=True)
    boxes = page.eval_on_selector_all("input.score", "boxes => boxes.map(box => box.parentElement.textContent)")
    points = [float(p) for text in boxes for p in re.findall(r"/\s*([0-9.]+)", text)]
    page.close()
    assert points, f"formgrader shows no score box for {sid}: {shot}\n{server.log_tail()}"
    return dialogs, points, shot


def test_the_class_was_graded_with_every_attacker_scored_as_an_honest_student(course):
    honest = course.results[HONEST]
    assert honest["score"] == honest["max_score"] > 0
    for name in ATTACKS:
        sid = student_id(load_entry(HOSTILE / f"{name}.py"))
        assert (course.results[sid]["status"], course.results[sid]["score"]) == ("graded", honest["score"]), name


def test_opening_an_attackers_submission_in_formgrader_runs_none_of_its_scripts(course, formgrader, browser, workdir,
                                                                                report_summary, monkeypatch):
    import grader.pipeline.unit as unit
    from grader.pipeline.plan import plan_units, unit_spec
    from grader.pipeline.run import GradeOptions

    started = time.monotonic()
    log_in(browser, formgrader)
    before = gradebook(course.db_url)
    source = nbformat.read(course.paths.source_notebooks("deformation")[0], as_version=4)
    source_points = [float(c.metadata.nbgrader["points"]) for c in source.cells if (c.metadata.get("nbgrader") or {}).get("grade")]
    attackers = [student_id(load_entry(HOSTILE / f"{name}.py")) for name in ATTACKS]
    lines = []
    for sid in attackers:
        dialogs, points, shot = open_as_ta(browser, formgrader, course.db_url, sid, workdir, "neutralized")
        assert dialogs == [], f"{sid}'s page opened dialogs {dialogs}: {shot}"
        assert points == source_points, f"{sid}'s page shows points {points}, the notebook has {source_points}: {shot}"
        assert gradebook(course.db_url) == before, f"opening {sid}'s submission changed the gradebook: {shot}"
    lines.append(f"  {len(attackers)} attackers' submissions opened: no dialog, gradebook unchanged "
                 f"({len(before)} grades and comments)")

    # Positive control: the same notebooks executed without neutralize, where formgrader reads them.
    monkeypatch.setattr(unit, "neutralize", lambda nb, source: [])
    monkeypatch.setenv("DEFORMLAB_ROOT", str(course.paths.root))
    options = GradeOptions(timeout=10)
    planned = {u.student_id: u for u in plan_units(course.submitted, course.paths.source_notebooks("deformation"), options, [])}
    # Forged cell metadata never reaches the executed notebook: sanitize rebuilds every cell's metadata from
    # the source before execution, so without neutralize too that attack stays inert; the control skips it.
    controlled = [sid for sid in attackers if sid != student_id(load_entry(HOSTILE / "cell_metadata_injects_html.py"))]
    for sid in controlled:
        raw = unit.grade_unit(unit_spec(planned[sid], SEED, options, planned[sid].source.read_text()),
                              [str(course.paths.data), str(course.paths.starter)])
        course.autograded(sid).write_text(raw["autograded_notebook"])
        dialogs, _, shot = open_as_ta(browser, formgrader, course.db_url, sid, workdir, "control")
        after = gradebook(course.db_url)
        changed = {key for key in after if after[key] != before[key]}
        assert dialogs and all(d.startswith("deformlab-attack:") for d in dialogs), f"{sid}: no script ran: {shot}"
        assert changed and {key[0] for key in changed} == {sid}, f"{sid}'s scripts changed {sorted(changed)}: {shot}"
        manual = [after[key] for key in changed if key[2].startswith("answer_")]
        assert manual and all(score[2] == 100 for score in manual), f"{sid}: {manual}"
        lines.append(f"  control {sid}: {len(dialogs)} script(s) ran ({', '.join(sorted(d.split(':')[1] for d in dialogs))}), "
                     f"{len(changed)} grade(s) rewritten")
        before = after
    report_summary("formgrader", "\n".join([f"formgrader in Chromium ({time.monotonic() - started:.1f} s):", *lines]))


def test_each_tests_cell_shows_its_verdicts_in_formgrader_as_text(course, formgrader, browser, workdir):
    log_in(browser, formgrader)
    texts = {}
    for sid in (HONEST, MARKUP):
        page = browser.new_page()
        dialogs: list[str] = []
        page.on("dialog", lambda dialog: (dialogs.append(dialog.message), dialog.dismiss()))
        page.goto(f"{formgrader.url}/formgrader/submissions/{submission_id(course.db_url, sid)}/?index=0")
        page.wait_for_load_state("networkidle")
        page.wait_for_timeout(SETTLE_S * 1000)
        page.screenshot(path=str(workdir / f"{sid}-verdicts.png"), full_page=True)
        texts[sid] = page.inner_text("body")
        assert page.locator("img[src=x]").count() == 0 and dialogs == [], f"{sid}: the message was rendered as markup"
        page.close()
    tests = course.results[MARKUP]["tests"]
    edges = next(t for t in tests if t["function"] == "edges")
    assert edges["score"] == 0 and edges["cases"]
    assert "ValueError: <img src=x onerror=alert('deformlab-attack:verdict')> not done" in edges["cases"][0]["error"]
    # Under each tests cell, the feedback page's verdict lines, word for word.
    for t in tests:
        assert f"{t['function']}: {t['score']:g} / {t['points']:g} points (hidden tests" in texts[MARKUP]
        for c in t["cases"]:
            assert f"- {c['label']}: {'passed' if c['passed'] else c['error'] or '; '.join(c['failed'])}" in texts[MARKUP]
    assert texts[HONEST].count("hidden cases passed") == len(course.results[HONEST]["tests"])


def test_each_written_answer_is_followed_by_the_model_answer_and_a_rubric_for_the_ta(course, formgrader, browser):
    log_in(browser, formgrader)
    source = nbformat.read(course.paths.source_notebooks("deformation")[0], as_version=4)
    answers = [(c.metadata.nbgrader["grade_id"], c.metadata.nbgrader["points"]) for c in source.cells
               if c.cell_type == "markdown" and (c.metadata.get("nbgrader") or {}).get("grade")]
    page = browser.new_page()
    page.goto(f"{formgrader.url}/formgrader/submissions/{submission_id(course.db_url, HONEST)}/?index=0")
    page.wait_for_load_state("networkidle")
    text = page.inner_text("body")
    page.close()
    notes = text.split("For the TA: not part of the student's notebook")[1:]
    assert answers and len(notes) == len(answers)
    for (_, points), note in zip(answers, notes):
        assert note.index(f"Model answer ({points:g} points)") < note.index("Rubric") < note.index("0: no answer")
