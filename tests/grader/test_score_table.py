"""The demo's score table keeps bonus points outside the regular total."""

from tests.demo import score_table


def unit(sid, notebook, score, max_score):
    return {"student_id": sid, "notebook": notebook, "score": score, "max_score": max_score}


def test_bonus_notebook_is_reported_beside_the_total_not_in_it():
    results = [unit("ada", "05_lbs", 10, 12), unit("ada", "06_fast", 7.5, 15), unit("bob", "05_lbs", 12, 12), unit("bob", "06_fast", 0, 15)]
    lines = score_table(results, ["ada", "bob"], ["05_lbs", "06_fast"]).splitlines()
    assert lines[0].split() == ["student", "05", "06+", "total", "bonus"]
    assert lines[1].split() == ["ada", "10/12", "7.5/15", "10/12", "+7.5"]
    assert lines[2].split() == ["bob", "12/12", "0/15", "12/12", "+0"]
    assert "bonus notebook" in lines[-1]
