"""``python -m benchmarks --refresh``: one benchmark's section is replaced, every other figure kept."""

from benchmarks.__main__ import MARK, _refreshed, _section

PREVIOUS = "## Run of earlier\n\n### bbw\n\n| figure | value |\n|---|---|\n| ratio | 0.9 |\n"


def results(figures):
    return "# Benchmark results\n\n" + _section(figures, "then") + f"\n{MARK}\n\n# Previous run\n\n{PREVIOUS}"


def test_refresh_replaces_only_the_named_section_of_the_latest_run():
    text = results({"arap": {"ratio": 0.5}, "bbw": {"ratio": 0.4}, "fast": {"speedup": 100.0}})
    new = _refreshed(text, {"bbw": {"ratio": 0.3}}, "now")
    head, _, previous = new.partition(MARK)
    assert "| ratio | 0.3 |" in head and "| ratio | 0.4 |" not in head
    assert "| ratio | 0.5 |" in head and "| speedup | 100 |" in head
    assert head.index("### arap") < head.index("### bbw") < head.index("### fast")
    assert "Re-measured alone at now" in head.split("### bbw")[1].split("### fast")[0]
    assert "Re-measured" not in head.split("### bbw")[0]
    assert previous.endswith(PREVIOUS)


def test_refresh_appends_a_benchmark_the_latest_run_lacks():
    text = results({"arap": {"ratio": 0.5}})
    head = _refreshed(text, {"arap_demo": {"fps": 29.0}}, "now").partition(MARK)[0]
    assert head.index("### arap\n") < head.index("### arap_demo\n")
    assert "| fps | 29 |" in head and "| ratio | 0.5 |" in head
