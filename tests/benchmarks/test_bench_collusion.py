"""``python -m benchmarks collusion`` at a class small enough for the suite: it runs, and what it reports holds.

The benchmark is not timed here; this keeps it runnable (it once imported a module
that had been removed, and ``make bench`` lost its collusion figures).
"""

from benchmarks.bench_collusion import ASSIGNMENT, NOTEBOOKS, run
from grader.build.source_notebook import build_sources


def test_a_small_synthetic_class_finds_every_planted_copy_and_ranks_as_the_exhaustive_pass(tmp_path):
    sources = {p.stem: p for p in build_sources(tmp_path / "source", ASSIGNMENT)}
    figures = run(60, sources, tmp_path, check_exhaustive=True)
    assert figures["60 students: planted copies found"] == "1 of 1"
    assert figures["60 students: same ranked pairs as the exhaustive pass"] is True
    assert not any(tmp_path.glob("submitted-*")), "the synthetic class is removed after the run"
    assert set(NOTEBOOKS) <= set(sources)
