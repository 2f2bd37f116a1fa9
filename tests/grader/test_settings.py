"""The kit's settings are declared traitlets (grader/settings.py), read from the course's nbgrader_config.py:
``deformlab grade`` takes its limits from ``c.Grading.*`` unless a flag overrides them, and a wrong setting is
refused naming the file and the setting."""

from __future__ import annotations

from pathlib import Path

import pytest

from grader import course_pack
from grader.cli import build_parser, grade_options, main
from grader.settings import SettingsError, grading_settings
from tests.course_copy import copy_course_config

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def course(tmp_path, monkeypatch):
    """A course folder whose nbgrader_config.py is the checkout's with ``extra`` appended."""

    def make(extra: str) -> Path:
        root = tmp_path / "course"
        root.mkdir()
        for name in ("notebooks", "starter", "data", "reference"):
            (root / name).symlink_to(ROOT / name)
        copy_course_config(root / "assignments", extra)
        monkeypatch.setenv("DEFORMLAB_ROOT", str(root))
        course_pack.forget()
        return root

    yield make
    course_pack.forget()


def _grade_args(*flags: str):
    return build_parser().parse_args(["grade", "submitted", "--out", "out", *flags])


def test_grading_limits_come_from_the_course_configuration_unless_a_flag_overrides_them(course):
    course("c.Grading.cell_timeout = 12.5\nc.Grading.notebook_wall = 300\nc.Grading.memory_gib = 2\n"
           "c.Grading.disk_mib = 256\nc.Grading.max_processes = 40\nc.Grading.workers = 3\n")
    options = grade_options(_grade_args())
    assert (options.timeout, options.wall, options.memory_gb, options.disk_bytes, options.max_processes, options.workers) == (
        12.5, 300.0, 2.0, 256 * 2**20, 40, 3)
    options = grade_options(_grade_args("--timeout", "7", "--workers", "1", "--disk", "64"))
    assert (options.timeout, options.workers, options.disk_bytes, options.wall) == (7.0, 1, 64 * 2**20, 300.0)


def test_without_settings_the_documented_defaults_apply(course):
    course("")
    options = grade_options(_grade_args())
    assert (options.timeout, options.wall, options.memory_gb, options.disk_bytes, options.workers) == (60.0, 900.0, 4.0, 2**30, None)


@pytest.mark.parametrize(
    ("setting", "named"),
    [
        ("c.Grading.cell_timeout = -1", "c.Grading.cell_timeout must be positive, got -1"),
        ("c.Grading.workers = -2", "c.Grading.workers must be 0 (one per core) or more"),
        ("c.Grading.memory_gib = 'lots'", "memory_gib"),
        ("c.Grading.timeout = 10", "c.Grading.timeout is not a setting of the kit"),
    ],
)
def test_a_wrong_grading_setting_is_refused_naming_the_file_and_the_setting(course, setting, named, capsys):
    root = course(setting + "\n")
    with pytest.raises(SettingsError) as refused:
        grading_settings(root / "assignments")
    assert str(root / "assignments" / "nbgrader_config.py") in str(refused.value) and named in str(refused.value)
    assert main(["grade", str(root / "nowhere"), "--out", str(root / "out")]) == 2
    assert named in capsys.readouterr().err
    assert not (root / "out").exists()
