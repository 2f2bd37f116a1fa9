"""log.jsonl keeps one record per student × notebook, the latest, whatever re-runs and crashes left in it."""

import json

from grader.pipeline.record import compact_log


def test_the_last_record_of_each_unit_is_kept_in_the_order_units_were_last_graded(tmp_path):
    records = [{"student_id": "a", "notebook": "x", "run": 1}, {"student_id": "b", "notebook": "x", "run": 1},
               {"student_id": "a", "notebook": "x", "run": 2}]
    (tmp_path / "log.jsonl").write_text("".join(json.dumps(r) + "\n" for r in records) + '{"student_id": "c", "note')
    compact_log(tmp_path)
    kept = [json.loads(line) for line in (tmp_path / "log.jsonl").read_text().splitlines()]
    assert kept == [records[1], records[2]], "a line cut by a crash is dropped"


def test_a_run_without_a_log_leaves_none(tmp_path):
    compact_log(tmp_path)
    assert not (tmp_path / "log.jsonl").exists()
