"""The contract tables in grader/contract.py match shared/CONTRACT.md, BONUS_CONTRACT.md, LECTURE_CONTRACT.md and reference/."""

import re
from pathlib import Path

import pytest

import reference
from grader.contract import BONUS_NAMES, BONUS_STAGES, CONTRACT_NAMES, LECTURE_NAMES, LECTURE_STAGES, MODULE_OF, STAGES

CONTRACT_MD = Path(__file__).resolve().parents[3] / "shared" / "CONTRACT.md"
BONUS_CONTRACT_MD = Path(__file__).resolve().parents[2] / "BONUS_CONTRACT.md"
LECTURE_CONTRACT_MD = Path(__file__).resolve().parents[2] / "LECTURE_CONTRACT.md"


def _table_names(path: Path) -> set[str]:
    return set(re.findall(r"^\| `([a-z_]+)\(", path.read_text(), flags=re.M))


@pytest.mark.skipif(not CONTRACT_MD.is_file(), reason="shared/CONTRACT.md is not beside this checkout")
def test_registry_lists_exactly_the_functions_of_contract_md_outside_the_bonus_and_lecture_tables():
    assert _table_names(CONTRACT_MD) == set(CONTRACT_NAMES - BONUS_NAMES - LECTURE_NAMES)


def test_bonus_stages_list_exactly_the_functions_of_bonus_contract_md():
    assert _table_names(BONUS_CONTRACT_MD) == set(BONUS_NAMES)
    assert BONUS_STAGES <= set(STAGES)


def test_lecture_tables_list_exactly_the_functions_of_lecture_contract_md_in_existing_stages():
    assert _table_names(LECTURE_CONTRACT_MD) == set(LECTURE_NAMES)
    assert set(LECTURE_STAGES) <= set(STAGES)
    assert not LECTURE_NAMES & BONUS_NAMES


def test_every_contract_function_is_importable_from_the_reference_package():
    missing = sorted(n for n in CONTRACT_NAMES if not callable(getattr(reference, n, None)))
    assert not missing, f"not exported by reference/__init__.py: {missing}"


def test_each_function_lives_in_its_stage_module():
    import importlib

    for stage, (module, names) in [*STAGES.items(), *LECTURE_STAGES.items()]:
        mod = importlib.import_module(f"reference.{module}")
        for name in names:
            assert getattr(mod, name).__module__ == f"reference.{MODULE_OF[name]}", (stage, name)
