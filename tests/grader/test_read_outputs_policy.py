"""The kernel's report of library-policy violations is hostile data: only the policy's own names count, and they cost the function."""

from __future__ import annotations

import json

import numpy as np

from grader.checks import CaseResult, FunctionResult, charge_policy
from grader.checks.base import Verdict
from grader.harness.outputs import MAX_POLICY_VIOLATIONS, policy_violations, read_outputs
from starter.library_policy import forbidden, message


def test_only_routines_the_policy_forbids_in_that_function_are_kept_once_as_the_graders_own_strings():
    reported = ["igl.cotmatrix", "igl.cotmatrix", "igl.lbs_matrix", 42, {"igl.cotmatrix": 1}, ["igl.cotmatrix"],
                "igl.cotmatrix_entries", "x" * 10**6, None]
    kept = policy_violations("cotangent_laplacian", reported)
    assert kept == ("igl.cotmatrix", "igl.cotmatrix_entries")
    assert all(any(k is r for r in forbidden("cotangent_laplacian")) for k in kept)


def test_anything_but_a_list_and_entries_past_the_cap_are_ignored():
    for reported in (None, "igl.cotmatrix", {"igl.cotmatrix": True}, 7):
        assert policy_violations("cotangent_laplacian", reported) == ()
    late = ["nothing"] * MAX_POLICY_VIOLATIONS + ["igl.cotmatrix"]
    assert policy_violations("cotangent_laplacian", late) == ()
    assert policy_violations("not_a_contract_function", ["igl.cotmatrix"]) == ()


def test_the_records_file_carries_them_to_the_collected_outputs(tmp_path):
    tmp_path.joinpath("out").mkdir()
    meta = {"records": [{"ok": True, "output": {"kind": "array"}, "seconds": 0.1}], "policy_violations": ["igl.cotmatrix"]}
    (tmp_path / "out" / "cotangent_laplacian.json").write_text(json.dumps(meta))
    np.savez(tmp_path / "out" / "cotangent_laplacian.npz", c0=np.eye(3))
    assert read_outputs("cotangent_laplacian", tmp_path / "out", 1).policy_violations == ("igl.cotmatrix",)


def test_a_violation_scores_the_function_zero_with_a_message_naming_the_routine_and_keeps_its_verdicts():
    passed = FunctionResult("cotangent_laplacian", [CaseResult("bar", [Verdict("values", True, "")])])
    assert charge_policy(passed, ()) is passed and passed.fraction == 1.0
    charged = charge_policy(passed, ("igl.cotmatrix",))
    assert charged.fraction == 0.0 and charged.cases[0].passed
    assert charged.summary() == message("cotangent_laplacian", "igl.cotmatrix")
    assert charged.policy_violations == ("igl.cotmatrix",)
