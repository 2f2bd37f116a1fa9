"""Course packs are read from their manifest, found by configuration, and refused with a message naming file and key."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import pytest

from grader import course_pack
from grader.course_pack import PackError, load_pack, pack

ROOT = Path(__file__).resolve().parents[2]

MANIFEST = """\
name = "tiny"
notebooks = "notebooks"
reference = "deformlab_packs.tiny.solution"
[[stages]]
notebook = "00_tiny"
functions = ["double"]
[[stages]]
notebook = "01_more"
functions = ["triple"]
bonus = true
"""


def _pack(tmp_path: Path, manifest: str = MANIFEST) -> Path:
    folder = tmp_path / "tiny"
    (folder / "notebooks").mkdir(parents=True)
    (folder / "assignment.toml").write_text(textwrap.dedent(manifest))
    return folder


def test_the_deformation_pack_is_the_course_default_with_its_ten_stages_and_two_bonus_ones():
    course = pack()
    assert course.name == "deformation"
    assert course.stage_names == ("00_meshes", "01_shape_matching", "02_sign_correction", "02b_k_harmonic", "03_arap",
                                  "03b_arap_global", "04_bbw", "05_lbs", "06_fast", "07_tetrahedra")
    assert [s.notebook for s in course.stages if s.bonus] == ["06_fast", "07_tetrahedra"]
    assert course.stage_of("arap_rotations") == "03_arap" and course.stage_of("arap_solve") == "03b_arap_global"
    assert course.is_bonus("06_fast") and not course.is_bonus("03_arap") and not course.is_bonus("03b_arap_global")
    assert course.notebooks == (ROOT / "notebooks" / "deformation").resolve()


def test_a_manifest_is_read_with_its_defaults(tmp_path):
    course = load_pack(_pack(tmp_path))
    assert (course.name, course.title, course.functions) == ("tiny", "tiny", ("double", "triple"))
    assert course.is_bonus("01_more") and not course.is_bonus("00_tiny") and course.stage_functions("nope") == ()
    assert course.readme is None and course.demos == () and course.policy == {}


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda m: m.replace('name = "tiny"', 'name = "Tiny Course"'), "name must be a lower-case identifier"),
        (lambda m: m.replace('"triple"', '"double"'), "function 'double' is graded by two stages: 00_tiny and 01_more"),
        (lambda m: m.replace('"00_tiny"', '"tiny"'), "stages[0].notebook must read NN_name"),
        (lambda m: m.replace("bonus = true", 'bonus = "yes"'), "stages[1].bonus must be true or false"),
        (lambda m: m.replace('notebooks = "notebooks"', 'notebooks = "elsewhere"'), "notebooks = 'elsewhere'"),
        (lambda m: m + "[policy]\nquadruple = []\n", "[policy] names functions no stage grades: ['quadruple']"),
        (lambda m: m.replace("[[stages]]", "[[stage]]"), "unknown keys ['stage']"),
        (lambda m: m.replace("bonus = true", "points = 3"), "stages[1] has unknown keys ['points']"),
        (lambda m: m + "= broken\n", "not valid TOML"),
        (lambda m: m.replace('functions = ["double"]', 'functions = ["dou ble"]'), "not identifiers"),
        (lambda m: m.replace('"01_more"', '"01bb_more"'), "stages[1].notebook must read NN_name or NNa_name"),
        (lambda m: m + '[grading]\nsteps = ["notes.py"]\n', "[grading] steps must read 'module:function'"),
        (lambda m: m + '[grading]\nstep = ["notes:hint"]\n', "[grading] has unknown keys ['step']"),
    ],
)
def test_a_malformed_manifest_is_refused_naming_the_file_and_the_key(tmp_path, change, message):
    folder = _pack(tmp_path, change(MANIFEST))
    with pytest.raises(PackError) as caught:
        load_pack(folder)
    assert message in str(caught.value)
    assert str(folder / "assignment.toml") in str(caught.value)


def test_a_stage_inserted_between_two_sorts_between_them():
    assert sorted(["03_arap", "02b_k_harmonic", "02_sign_correction"]) == ["02_sign_correction", "02b_k_harmonic", "03_arap"]


def test_a_pack_s_grading_step_that_cannot_be_loaded_is_refused_naming_the_manifest_and_the_step(tmp_path):
    folder = _pack(tmp_path, MANIFEST + '[grading]\nsteps = ["notes:hint"]\n')
    (folder / "notes.py").write_text("def other(unit):\n    pass\n")
    course = load_pack(folder)
    assert course.steps == ("notes:hint",)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(course_pack, "packs", lambda: {"tiny": course})
        try:
            with pytest.raises(PackError) as caught:
                course.grading_steps()
        finally:  # this folder's modules must not answer for another test's pack named tiny
            for name in [n for n in sys.modules if n.startswith("deformlab_packs.tiny")]:
                del sys.modules[name]
    assert str(folder / "assignment.toml") in str(caught.value) and "'notes:hint' cannot be loaded" in str(caught.value)


def test_a_folder_without_a_manifest_is_not_a_pack(tmp_path):
    with pytest.raises(PackError, match="not a course pack"):
        load_pack(tmp_path)


def _course(tmp_path: Path, config: str) -> Path:
    root = tmp_path / "course"
    for name in ("data", "notebooks"):
        (root / name).mkdir(parents=True)
    (root / "assignments").mkdir()
    (root / "assignments" / "nbgrader_config.py").write_text("c = get_config()\n" + config)
    return root


def test_packs_are_found_from_the_configuration_and_their_code_imports_as_deformlab_packs(tmp_path, monkeypatch):
    folder = _pack(tmp_path)
    (folder / "solution.py").write_text("def double(x):\n    return 2 * x\n\n\ndef triple(x):\n    return 3 * x\n")
    root = _course(tmp_path, f"c.DeformLab.course_packs = [{str(folder)!r}]\n")
    monkeypatch.setenv("DEFORMLAB_ROOT", str(root))
    course_pack.forget()
    try:
        assert list(course_pack.packs()) == ["tiny"] and course_pack.default_assignment() == "tiny"
        assert pack("tiny").reference_function("triple")(2) == 6
        from deformlab_packs.tiny import solution

        assert solution.double(4) == 8
        with pytest.raises(PackError, match="no course pack declares assignment 'deformation'"):
            pack("deformation")
    finally:
        course_pack.forget()


def test_without_the_setting_every_folder_with_a_manifest_is_a_pack_and_a_wrong_default_is_refused(tmp_path, monkeypatch):
    root = _course(tmp_path, 'c.DeformLab.default_assignment = "other"\n')
    _pack(root / "assignments")
    monkeypatch.setenv("DEFORMLAB_ROOT", str(root))
    course_pack.forget()
    try:
        with pytest.raises(PackError, match="default_assignment = 'other' is not a pack"):
            course_pack.packs()
    finally:
        course_pack.forget()
