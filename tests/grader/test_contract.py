"""The deformation pack's stages (assignments/deformation/assignment.toml) match shared/CONTRACT.md, BONUS_CONTRACT.md,
LECTURE_CONTRACT.md and reference/."""

import re
from pathlib import Path

import pytest

import reference
from grader.course_pack import pack

ROOT = Path(__file__).resolve().parents[2]
CONTRACT_MD = ROOT.parent / "shared" / "CONTRACT.md"
BONUS_CONTRACT_MD = ROOT / "BONUS_CONTRACT.md"
LECTURE_CONTRACT_MD = ROOT / "LECTURE_CONTRACT.md"
COURSE = pack("deformation")
BONUS_NAMES = {f for s in COURSE.stages if s.bonus for f in s.functions}


def _table_names(path: Path) -> set[str]:
    return set(re.findall(r"^\| `([a-z_]+)\(", path.read_text(), flags=re.M))


@pytest.mark.skipif(not CONTRACT_MD.is_file(), reason="shared/CONTRACT.md is not beside this checkout")
def test_the_pack_grades_exactly_the_functions_of_the_three_contract_files():
    assert _table_names(CONTRACT_MD) == set(COURSE.function_names) - BONUS_NAMES - _table_names(LECTURE_CONTRACT_MD)


def test_the_bonus_stages_grade_the_functions_of_bonus_contract_md_and_the_tetrahedra_of_lecture_contract_md():
    assert [s.notebook for s in COURSE.stages if s.bonus] == ["06_fast", "07_tetrahedra"]
    assert _table_names(BONUS_CONTRACT_MD) == set(COURSE.stage_functions("06_fast"))
    assert BONUS_NAMES == set(COURSE.stage_functions("06_fast")) | set(COURSE.stage_functions("07_tetrahedra"))


def test_lecture_contract_functions_are_graded_by_existing_stages_and_only_the_tetrahedra_are_bonus():
    lecture = _table_names(LECTURE_CONTRACT_MD)
    assert lecture <= COURSE.function_names
    assert lecture & BONUS_NAMES == set(COURSE.stage_functions("07_tetrahedra"))


def test_every_graded_function_is_exported_by_the_reference_package():
    missing = sorted(n for n in COURSE.function_names if not callable(getattr(reference, n, None)))
    assert not missing, f"not exported by reference/__init__.py: {missing}"


def test_each_stage_lists_its_functions_in_the_order_its_notebook_teaches_them():
    from grader.build.authored import read_authored

    for stage in COURSE.stages:
        authored = read_authored(COURSE.notebooks / f"{stage.notebook}.py", COURSE)
        own = [c.function for c in authored.cells if c.kind == "solution" and c.function in stage.functions]
        assert own == list(stage.functions), stage.notebook
