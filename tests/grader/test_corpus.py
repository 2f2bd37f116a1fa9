"""The whole corpus (tests/corpus) graded in one run: bugs lose exactly their points, attacks are stopped.

One ``grade_class`` run over every corpus submission (one notebook per student)
is shared by the module; each entry then asserts its own expectation
(``grader/corpus.py`` describes the files).
"""

from __future__ import annotations

import csv
import os
import secrets
import shutil
import socket
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

from grader.contract import STAGES
from grader.corpus import CorpusEntry, build_submission, load_corpus, student_id
from grader.pipeline.run import GradeOptions, grade_class

ROOT = Path(__file__).resolve().parents[2]
ENTRIES = load_corpus(ROOT / "tests" / "corpus")
SEED = 20240611


class Listener:
    """A TCP listener on 127.0.0.1 that counts the connections it accepts."""

    def __init__(self):
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.connections = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self):
        while not self._stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except (TimeoutError, OSError):
                continue
            self.connections += 1
            conn.close()

    def close(self):
        self._stop.set()
        self._thread.join()
        self.sock.close()


@dataclass
class Graded:
    results: dict[tuple[str, str], dict]
    csv_rows: list[dict]
    params: dict[str, str]
    connections: int
    seconds: float

    def result(self, entry: CorpusEntry) -> dict:
        return self.results[(student_id(entry), entry.notebook)]


def _course_root(tmp: Path, source_notebooks: dict[str, Path]) -> Path:
    """A course root whose assignments/ is private to this test; data/, starter/, notebooks/ are the checkout's."""
    root = tmp / "course"
    source = root / "assignments" / "source" / "deformation"
    source.mkdir(parents=True)
    for name in ("data", "starter", "notebooks"):
        (root / name).symlink_to(ROOT / name)
    for path in source_notebooks.values():
        shutil.copy(path, source / path.name)
    return root


def _processes_with(text: str) -> list[int]:
    found = []
    for proc in Path("/proc").iterdir():
        if proc.name.isdigit():
            try:
                if text.encode() in (proc / "cmdline").read_bytes():
                    found.append(int(proc.name))
            except OSError:
                continue
    return found


@pytest.fixture(scope="module")
def graded(source_notebooks, tmp_path_factory) -> Graded:
    tmp = tmp_path_factory.mktemp("corpus")
    listener = Listener()
    params = {"REPO": str(ROOT), "PORT": str(listener.port), "TOKEN": secrets.token_hex(6)}
    root = _course_root(tmp, source_notebooks)
    submitted = tmp / "submitted"
    for entry in ENTRIES:
        build_submission(entry, root / "assignments" / "source" / "deformation", submitted, student_id(entry), params)
    markers = [Path(entry.fill(p, params)) for entry in ENTRIES for p in entry.must_not_exist]
    try:
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv("DEFORMLAB_ROOT", str(root))
            # nbgrader's Gradebook runs the `alembic` script of this environment
            mp.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
            started = time.monotonic()
            results = grade_class(
                submitted,
                tmp / "out",
                GradeOptions(workers=2, timeout=10, db_url=f"sqlite:///{tmp}/gb.db", seed=SEED, progress=False),
            )
            seconds = time.monotonic() - started
    finally:
        listener.close()
    with open(tmp / "out" / "grades.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    yield Graded({(r["student_id"], r["notebook"]): r for r in results}, rows, params, listener.connections, seconds)
    for marker in markers:  # never leave an escaped marker behind, whatever the assertions said
        marker.unlink(missing_ok=True)


def lost_functions(result: dict) -> set[str]:
    return {t["function"] for t in result["tests"] if t["score"] < t["points"]}


def expectation_failures(entry: CorpusEntry, result: dict, graded: Graded) -> list[str]:
    """What in ``result`` (and on the host) differs from the entry's expectation; empty if it held."""
    problems = []
    if entry.status and result["status"] != entry.status:
        problems.append(f"status {result['status']!r}, expected {entry.status!r}: {result['reasons'][:2]}")
    if not entry.status and result["status"] not in ("graded", "graded-with-incidents"):
        problems.append(f"status {result['status']!r}: {result['reasons'][:2]}")
    lost = lost_functions(result)
    for t in result["tests"]:
        if t["function"] in lost - entry.loses:
            problems.append(f"{t['function']} lost points it should keep ({t['score']}/{t['points']}): {t['summary']}")
    for f in sorted(entry.loses - lost):
        problems.append(f"{f} kept full marks although it should lose points")
    for path in entry.must_not_exist:
        if Path(entry.fill(path, graded.params)).exists():
            problems.append(f"{entry.fill(path, graded.params)} exists: the submission wrote outside its workdir")
    if entry.no_process:
        pids = _processes_with(entry.fill(entry.no_process, graded.params))
        if pids:
            problems.append(f"processes {pids} started by the submission outlived its kernel")
    if entry.listener and graded.connections:
        problems.append(f"the listener on 127.0.0.1 accepted {graded.connections} connection(s)")
    return problems


@pytest.mark.parametrize("entry", ENTRIES, ids=lambda e: f"{e.kind}/{e.name}")
def test_corpus_entry_gets_exactly_its_expected_grade(graded, entry):
    result = graded.result(entry)
    assert not expectation_failures(entry, result, graded), "\n".join(expectation_failures(entry, result, graded))
    if entry.kind == "correct":
        assert result["score"] == result["max_score"]
    others = [r for (sid, nb), r in graded.results.items() if sid == student_id(entry) and nb != entry.notebook]
    assert {r["status"] for r in others} == {"missing"}


def test_grades_csv_has_one_row_per_student_and_notebook(graded):
    pairs = [(row["student_id"], row["notebook"]) for row in graded.csv_rows]
    expected = {(student_id(e), nb) for e in ENTRIES for nb in STAGES}
    assert len(pairs) == len(set(pairs))
    assert set(pairs) == expected


def test_corpus_summary(graded, capsys):
    counts = {kind: [0, 0] for kind in ("buggy", "correct", "hostile")}
    lines = []
    for entry in ENTRIES:
        result = graded.result(entry)
        problems = expectation_failures(entry, result, graded)
        counts[entry.kind][0] += not problems
        counts[entry.kind][1] += 1
        flag = "ok " if not problems else "BAD"
        lines.append(
            f"  {flag} {entry.kind:<8} {entry.name:<34} {entry.notebook:<19} {result['status']:<22} "
            f"{result['score']:g}/{result['max_score']:g}  {result.get('duration_s', 0):5.1f} s"
        )
    with capsys.disabled():
        print(f"\ncorpus graded in {graded.seconds:.1f} s ({len(graded.results)} units, 2 workers, timeout 10 s):")
        print("\n".join(lines))
        print(
            f"  buggy caught (exactly their functions lose): {counts['buggy'][0]}/{counts['buggy'][1]}; "
            f"correct with full marks: {counts['correct'][0]}/{counts['correct'][1]}; "
            f"hostile stopped: {counts['hostile'][0]}/{counts['hostile'][1]}"
        )
    assert all(ok == total for ok, total in counts.values())
