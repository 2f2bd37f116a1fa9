"""The `deformlab` command's own surface: version, help, and options that cannot work are refused up front."""

import argparse

import time

import pytest

from grader.cli import build_parser, main


def test_version_names_the_installed_package(capsys):
    from importlib.metadata import version

    with pytest.raises(SystemExit) as stop:
        main(["--version"])
    assert stop.value.code == 0
    assert capsys.readouterr().out.strip() == f"deformlab {version('deformlab')}"


def test_help_is_plain_text_and_every_option_is_explained(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "``" not in capsys.readouterr().out, "no raw reStructuredText in --help"
    commands = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)).choices
    assert set(commands) >= {"build", "release", "grade", "gradescope", "check"}
    for name, sub in commands.items():
        for action in sub._actions:
            assert action.help, f"deformlab {name} {'/'.join(action.option_strings) or action.dest}: no help text"


@pytest.mark.parametrize(
    ("option", "value", "message"),
    [
        ("--memory", "-1", "must be a positive number"),
        ("--memory", "0.01", "a kernel needs at least"),
        ("--timeout", "-5", "must be a positive number"),
        ("--timeout", "nan", "must be a positive number"),
        ("--workers", "0", "must be a positive integer"),
    ],
)
def test_grade_options_that_cannot_work_are_usage_errors(tmp_path, capsys, option, value, message):
    with pytest.raises(SystemExit) as stop:
        main(["grade", str(tmp_path), "--out", str(tmp_path / "o"), option, value])
    assert stop.value.code == 2
    assert f"{option}: {message}" in capsys.readouterr().err


def test_a_folder_without_student_assignment_folders_is_refused_and_adds_no_student(tmp_path, capsys):
    from nbgrader.api import Gradebook

    wrong = tmp_path / "wrong"
    (wrong / "notes").mkdir(parents=True)
    (wrong / "out").mkdir()
    db = f"sqlite:///{tmp_path}/gb.db"
    assert main(["grade", str(wrong), "--out", str(wrong / "out"), "--db", db]) == 2
    assert "holds no <student>/deformation/ folder" in capsys.readouterr().err
    with Gradebook(db) as gb:
        assert [s.id for s in gb.students] == []


def test_grade_exits_nonzero_when_a_notebook_could_not_be_graded(tmp_path, capsys, monkeypatch):
    import grader.pipeline.run as run

    def fake(submitted, out, options):
        from grader.pipeline.record import write_grades_csv

        results = [{"student_id": "ada", "assignment": "deformation", "notebook": "01_shape_matching", "score": 0, "max_score": 10,
                    "status": "grader-error", "tests": []}]
        out.mkdir()
        write_grades_csv(out, results)
        return results

    monkeypatch.setattr(run, "grade_class", fake)
    assert main(["grade", str(tmp_path), "--out", str(tmp_path / "o")]) == 1
    assert "1 notebook(s) could not be graded" in capsys.readouterr().err


def test_a_late_policy_without_a_due_date_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "ada" / "deformation").mkdir(parents=True)
    db = f"sqlite:///{tmp_path}/gb.db"  # a gradebook without the assignment: no due date there either
    assert main(["grade", str(tmp_path), "--out", str(tmp_path / "o"), "--late-policy", "zero", "--db", db]) == 2
    assert "--late-policy needs a due date: --due, or the gradebook's" in capsys.readouterr().err


def test_without_flags_the_due_date_comes_from_the_gradebook_and_the_plugin_from_nbgrader_config(tmp_path, monkeypatch):
    from datetime import datetime

    from nbgrader.api import Gradebook
    from nbgrader.plugins import LateSubmissionPlugin

    import grader.late_policy as late_policy
    import grader.pipeline.run as run

    db = f"sqlite:///{tmp_path}/gb.db"
    with Gradebook(db) as gb:
        gb.add_assignment("deformation", duedate=datetime(2026, 11, 20, 22, 59))
    (tmp_path / "ada" / "deformation").mkdir(parents=True)
    seen = {}
    monkeypatch.setattr(run, "grade_class", lambda submitted, out, options: [])
    monkeypatch.setattr(late_policy, "apply_late_policy",
                        lambda out, submitted, assignment, due, plugin, db_url, **kw: seen.update(due=due, plugin=plugin) or {})
    main(["grade", str(tmp_path), "--out", str(tmp_path / "o"), "--db", db])
    assert seen["due"] == datetime(2026, 11, 20, 22, 59)
    # the course's nbgrader_config.py sets no plugin: nbgrader's own, which charges nothing
    assert type(seen["plugin"]) is LateSubmissionPlugin and seen["plugin"].penalty_method == "none"
    main(["grade", str(tmp_path), "--out", str(tmp_path / "o"), "--db", db, "--due", "2026-11-21 12:00:00 UTC", "--late-policy", "zero"])
    assert seen["due"] == datetime(2026, 11, 21, 12) and seen["plugin"].penalty_method == "zero"


def test_an_unreadable_due_date_is_a_usage_error(tmp_path, capsys):
    assert main(["grade", str(tmp_path), "--out", str(tmp_path / "o"), "--due", "soon"]) == 2
    assert "--due 'soon' is not a date" in capsys.readouterr().err


def test_a_wrong_submitted_folder_is_refused_at_once_before_building_or_writing_anything(tmp_path, capsys):
    wrong = tmp_path / "wrong"
    (wrong / "notes").mkdir(parents=True)
    out = tmp_path / "out"
    started = time.process_time()
    assert main(["grade", str(wrong), "--out", str(out)]) == 2
    # the refusal builds no notebook and runs no nbgrader: a fraction of a CPU-second (building took 30 s)
    assert time.process_time() - started < 1.0
    assert "holds no <student>/deformation/ folder" in capsys.readouterr().err
    assert not out.exists()


def test_an_assignment_no_course_pack_declares_is_refused_naming_the_course_s_assignments(tmp_path, capsys):
    (tmp_path / "s" / "alice" / "geometry").mkdir(parents=True)
    assert main(["grade", str(tmp_path / "s"), "--out", str(tmp_path / "out"), "--assignment", "geometry"]) == 2
    err = capsys.readouterr().err
    assert "no course pack declares assignment 'geometry'" in err and "'deformation', 'smoothing'" in err
