"""The whole corpus (tests/corpus) graded in one run: bugs lose exactly their points, attacks are stopped.

One ``grade_class`` run over every corpus submission (one notebook per student)
is shared by the module; each entry then asserts its own expectation
(``tests/corpus/__init__.py`` describes the files).
"""

from __future__ import annotations

import csv
import fcntl
import json
import os
import secrets
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import nbformat
import pytest

from grader.course_pack import pack
_COURSE = pack("deformation")
STAGES = _COURSE.stage_names
from tests.corpus import CorpusEntry, build_submission, load_corpus, student_id, student_notebook
from grader.pipeline.run import GradeOptions, grade_class
from grader.sandbox.process_limit import pids_parent
from grader.sandbox.workspace import PREFIX as WORKSPACE_PREFIX

ROOT = Path(__file__).resolve().parents[2]
# Entries that fork until refused are only safe where the sandbox caps processes.
_ALL_ENTRIES = load_corpus(ROOT / "tests" / "corpus")
CAPPED = pids_parent() is not None
ENTRIES = [e for e in _ALL_ENTRIES if CAPPED or not e.needs_process_cap]
LEFT_OUT = sorted(e.name for e in _ALL_ENTRIES if e not in ENTRIES)
SEED = 20240611
# Small limits, so that the attacks on them are quick: a 45 s notebook and a 512 MiB workdir.
#: seconds a cell may run: a hanging entry is stopped by it, a busy machine never is (10 s was, under load)
CELL_TIMEOUT = 20
WALL = 45.0
DISK_BYTES = 512 * 2**20

pytestmark = [
    pytest.mark.slow,
    # cells_duplicated hands in repeated cell ids on purpose; nbformat warns when it reads them
    pytest.mark.filterwarnings("ignore::nbformat.warnings.DuplicateCellId"),
]


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


class Decoys:
    """What attacks on the host aim at, made by the test: a folder with a secret, and a process whose
    command line names a path in it. Never a real system path or PID 1 (the tests run as root)."""

    def __init__(self, tmp: Path, token: str):
        self.folder = tmp / f"decoy-{token}"
        self.folder.mkdir()
        self.secret = f"decoy-secret-{token}"
        (self.folder / "secret.txt").write_text(self.secret)
        (self.folder / "victim-arg").write_text("")
        self.process = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(3600)", str(self.folder / "victim-arg")])
        self.listing = self._listing()

    def _listing(self) -> dict[str, bytes]:
        return {p.name: p.read_bytes() for p in sorted(self.folder.iterdir())}

    def problems(self) -> list[str]:
        found = []
        if self.process.poll() is not None:
            found.append(f"the decoy process died (exit {self.process.returncode})")
        if self._listing() != self.listing:
            found.append(f"the decoy folder changed: {sorted(self._listing())} != {sorted(self.listing)}")
        return found

    def close(self) -> None:
        self.process.kill()
        self.process.wait()


def _host_leftovers() -> set[str]:
    """Work folders and per-sandbox cgroups no live grader holds, to compare before and after a run
    (other test workers may be grading at the same time: their folders are locked, their cgroups' owners alive)."""
    found = set()
    for lock_path in Path(tempfile.gettempdir()).glob(f"{WORKSPACE_PREFIX}*.lock"):
        try:
            with open(lock_path) as lock:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:  # held: a grader is using it (or it was just removed)
            continue
        found.add(lock_path.stem)
    parent = pids_parent()
    if parent is not None:
        owners = {p: p.name.split("-")[1] for p in parent.glob("deformlab-*-*")}
        found |= {p.name for p, pid in owners.items() if pid.isdigit() and not Path(f"/proc/{pid}").exists()}
    return found


@dataclass
class Graded:
    results: dict[tuple[str, str], dict]
    csv_rows: list[dict]
    params: dict[str, str]
    connections: int
    seconds: float
    host_problems: list[str]

    def result(self, entry: CorpusEntry) -> dict:
        return self.results[(student_id(entry), entry.notebook)]


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
def graded(tmp_path_factory, make_course) -> Iterator[Graded]:
    tmp = tmp_path_factory.mktemp("corpus")
    listener = Listener()
    token = secrets.token_hex(6)
    decoys = Decoys(tmp, token)
    params = {
        "REPO": str(ROOT), "PORT": str(listener.port), "TOKEN": token, "DECOY": str(decoys.folder),
        "DISK_BYTES": str(DISK_BYTES), "WALL": str(WALL),
    }
    before = _host_leftovers()
    root = make_course(tmp)
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
                GradeOptions(
                    workers=2, timeout=CELL_TIMEOUT, wall=WALL, disk_bytes=DISK_BYTES,
                    db_url=f"sqlite:///{tmp}/gb.db", seed=SEED, progress=False,
                ),
            )
            seconds = time.monotonic() - started
        host_problems = decoys.problems()
        host_problems += [f"{name} was left on the host" for name in sorted(_host_leftovers() - before)]
        shown = json.dumps(results)
        if decoys.secret in shown:
            host_problems.append("the decoy secret appears in a result (feedback, reasons or notes)")
    finally:
        listener.close()
        decoys.close()
    with open(tmp / "out" / "grades.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    yield Graded({(r["student_id"], r["notebook"]): r for r in results}, rows, params, listener.connections, seconds, host_problems)
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
    if entry.event and not any(entry.event in event for event in result.get("events", [])):
        problems.append(f"no recorded event mentions {entry.event!r}; events: {result.get('events', [])}")
    if entry.check:
        problems += entry.check(result, result.get("autograded_notebook"), graded.params)
    if entry.listener and graded.connections:
        problems.append(f"the listener on 127.0.0.1 accepted {graded.connections} connection(s)")
    return problems


def test_student_notebook_replaces_named_solution_cells_and_strips_the_markers(source_notebooks):
    source = nbformat.read(source_notebooks["02_sign_correction"], as_version=4)
    nb = student_notebook(source, {"rigid_align": "def rigid_align(P, Q, w=None):\n    return None\n"})
    solution = {c.metadata["nbgrader"]["grade_id"]: c.source for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("solution")}
    original = {c.metadata["nbgrader"]["grade_id"]: c.source for c in source.cells if (c.metadata.get("nbgrader") or {}).get("solution")}
    assert solution["solution_rigid_align"] == "def rigid_align(P, Q, w=None):\n    return None\n"
    for gid, text in solution.items():
        assert "### BEGIN SOLUTION" not in text and "### END SOLUTION" not in text
        if gid != "solution_rigid_align":
            kept = [line for line in original[gid].splitlines() if "### " not in line]
            assert text.splitlines() == kept
    assert [c.source for c in nb.cells if not (c.metadata.get("nbgrader") or {}).get("solution")] == [
        c.source for c in source.cells if not (c.metadata.get("nbgrader") or {}).get("solution")
    ]


def test_every_corpus_entry_builds_into_its_student_folder(source_notebooks, tmp_path):
    params = {"REPO": str(ROOT), "PORT": "1", "TOKEN": "t", "DECOY": str(tmp_path / "decoy"), "DISK_BYTES": "1", "WALL": "1"}
    for entry in ENTRIES:
        path = build_submission(entry, source_notebooks[entry.notebook].parent, tmp_path, student_id(entry), params)
        assert path == tmp_path / student_id(entry) / "deformation" / (entry.filename or f"{entry.notebook}.ipynb")
        assert "@@" not in path.read_text(errors="replace")


def _param(entry: CorpusEntry):
    # strict: once the check is fixed the test passes, fails as XPASS, and WEAK_CHECK must go
    marks = [pytest.mark.xfail(strict=True, reason=entry.weak_check)] if entry.weak_check else []
    return pytest.param(entry, id=f"{entry.kind}/{entry.name}", marks=marks)


@pytest.mark.parametrize("entry", [_param(e) for e in ENTRIES])
def test_corpus_entry_gets_exactly_its_expected_grade(graded, entry):
    result = graded.result(entry)
    assert not expectation_failures(entry, result, graded), "\n".join(expectation_failures(entry, result, graded))
    if entry.kind == "correct":
        assert result["score"] == result["max_score"]
    others = {nb: r for (sid, nb), r in graded.results.items() if sid == student_id(entry) and nb != entry.notebook}
    if entry.source:
        # the file's own metadata names its notebook: it is graded as that one too, as a renamed file
        moved = others.pop(entry.source)
        assert moved["score"] == moved["max_score"] and any("renamed file" in n for n in moved["notes"])
    assert {r["status"] for r in others.values()} == {"missing"}


def test_the_host_is_as_it_was_decoys_untouched_no_secret_shown_nothing_left(graded):
    assert not graded.host_problems, "\n".join(graded.host_problems)


def test_grades_csv_has_one_row_per_student_and_notebook(graded):
    pairs = [(row["student_id"], row["notebook"]) for row in graded.csv_rows]
    expected = {(student_id(e), nb) for e in ENTRIES for nb in STAGES}
    assert len(pairs) == len(set(pairs))
    assert set(pairs) == expected


def test_corpus_summary(graded, report_summary):
    counts = {kind: [0, 0] for kind in ("buggy", "correct", "hostile")}
    weak, lines = [], []
    for entry in ENTRIES:
        result = graded.result(entry)
        held = not expectation_failures(entry, result, graded)
        if entry.weak_check:
            weak.append(entry.name)
        else:
            counts[entry.kind][0] += held
            counts[entry.kind][1] += 1
        flag = "ok " if held else ("weak" if entry.weak_check else "BAD")
        lines.append(
            f"  {flag:<4} {entry.kind:<8} {entry.name:<34} {entry.notebook:<19} {result['status']:<22} "
            f"{result['score']:g}/{result['max_score']:g}  {result.get('duration_s', 0):5.1f} s"
        )
    peaks = [(r.get("grader_peak_rss_bytes") or 0, sid, nb) for (sid, nb), r in graded.results.items()]
    peak, peak_sid, peak_nb = max(peaks)
    summary = "\n".join(
        [
            f"corpus graded in {graded.seconds:.1f} s ({len(graded.results)} units, 2 workers, timeout 10 s):",
            f"  grading process's peak resident memory over one unit: {peak / 2**20:.0f} MiB at most ({peak_sid} {peak_nb})",
            *lines,
            f"  buggy caught (exactly their functions lose): {counts['buggy'][0]}/{counts['buggy'][1]}; "
            f"correct with full marks: {counts['correct'][0]}/{counts['correct'][1]}; "
            f"hostile stopped: {counts['hostile'][0]}/{counts['hostile'][1]}; "
            f"known weak checks (expected failures): {len(weak)} {weak}",
            *([] if CAPPED else [f"  left out, no pids cgroup to cap processes here: {LEFT_OUT}"]),
        ]
    )
    # Shown at the end of the run by tests/conftest.py (an xdist worker's own prints are not relayed).
    report_summary("corpus", summary)
    assert all(ok == total for ok, total in counts.values())
