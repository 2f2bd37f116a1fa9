"""The gradebook on a real PostgreSQL server: grading writes it, ``nbgrader export`` reads it, concurrent runs lose nothing.

The server is Debian's ``postgresql`` (the Makefile installs it), started by the
tests on a private socket folder and a free port of 127.0.0.1, as an
unprivileged user when the tests run as root (PostgreSQL refuses to run as root).
"""

from __future__ import annotations

import csv
import os
import shutil
import socket
import subprocess
import sys
import tempfile
from pathlib import Path

import nbformat
import pytest

from tests.corpus import student_notebook
from grader.paths import CoursePaths
from grader.pipeline.run import GradeOptions, grade_class

psycopg = pytest.importorskip("psycopg", reason='the postgres extra is not installed: pip install "deformlab[postgres]"')
pytestmark = pytest.mark.slow

NOTEBOOK = "01_shape_matching"
NOBODY = 65534
BIN = Path(sys.executable).parent


def _server_binaries() -> Path | None:
    found = sorted(Path("/usr/lib/postgresql").glob("*/bin/initdb"), key=lambda p: int(p.parent.parent.name))
    return found[-1].parent if found else None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class PostgresServer:
    """A throw-away PostgreSQL cluster: ``initdb``, ``pg_ctl start``, superuser ``deformlab`` trusted on loopback."""

    def __init__(self, bindir: Path):
        self.bindir = bindir
        self.folder = Path(tempfile.mkdtemp(prefix="dl-pg-"))
        self.data = self.folder / "data"
        self.port = _free_port()
        self.as_user = [] if os.geteuid() != 0 else ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups", "--"]
        if self.as_user:
            os.chown(self.folder, NOBODY, NOBODY)
        self._run("initdb", "-D", str(self.data), "-U", "deformlab", "--auth=trust", "-E", "UTF8", "--no-sync", "--no-instructions")
        self._run(
            "pg_ctl", "-D", str(self.data), "-l", str(self.folder / "server.log"), "-w", "-t", "60",
            "-o", f"-c listen_addresses=127.0.0.1 -p {self.port} -k {self.folder} -c fsync=off",
            "start",
        )

    def _run(self, tool: str, *args: str) -> None:
        subprocess.run([*self.as_user, str(self.bindir / tool), *args], check=True, capture_output=True, cwd=self.folder, timeout=120)

    def create_database(self, name: str) -> str:
        """A new database; its SQLAlchemy URL."""
        with psycopg.connect(host="127.0.0.1", port=self.port, user="deformlab", dbname="postgres", autocommit=True) as conn:
            conn.execute(f'CREATE DATABASE "{name}"')
        return f"postgresql+psycopg://deformlab@127.0.0.1:{self.port}/{name}"

    def query(self, url: str, sql: str) -> list[tuple]:
        with psycopg.connect(host="127.0.0.1", port=self.port, user="deformlab", dbname=url.rsplit("/", 1)[1]) as conn:
            return conn.execute(sql).fetchall()

    def stop(self) -> None:
        self._run("pg_ctl", "-D", str(self.data), "-m", "immediate", "stop")
        shutil.rmtree(self.folder, ignore_errors=True)


@pytest.fixture(scope="module")
def server():
    bindir = _server_binaries()
    if bindir is None:
        reason = "PostgreSQL server binaries not found under /usr/lib/postgresql (make setup installs Debian's postgresql as root)"
        print(f"\nskipped: {reason}")
        pytest.skip(reason)
    pg = PostgresServer(bindir)
    yield pg
    pg.stop()


def _submit(submitted: Path, student: str, source: Path | None) -> None:
    """A student folder; with the notebook solved (from the instructor notebook ``source``) if given."""
    folder = submitted / student / "deformation"
    folder.mkdir(parents=True)
    if source is not None:
        nbformat.write(student_notebook(nbformat.read(source, as_version=4), {}), folder / f"{NOTEBOOK}.ipynb")


def _scores(pg: PostgresServer, url: str) -> dict[tuple[str, str], float]:
    """Autograded score per student × notebook, as nbgrader's tables hold it."""
    rows = pg.query(
        url,
        """SELECT s.student_id, n.name, SUM(COALESCE(g.auto_score, 0))
           FROM grade g JOIN submitted_notebook s_nb ON g.notebook_id = s_nb.id
           JOIN notebook n ON s_nb.notebook_id = n.id
           JOIN submitted_assignment s ON s_nb.assignment_id = s.id
           GROUP BY s.student_id, n.name""",
    )
    return {(sid, nb): float(score) for sid, nb, score in rows}


@pytest.fixture(scope="module")
def graded(server, source_notebooks, make_course):
    """A class of two (one correct notebook, one garbage file) graded into a fresh PostgreSQL database."""
    tmp = Path(tempfile.mkdtemp(prefix="dl-pgc-"))
    root = make_course(tmp)
    submitted = tmp / "submitted"
    _submit(submitted, "Ada_Lovelace", source_notebooks[NOTEBOOK])
    _submit(submitted, "bob", None)
    (submitted / "bob" / "deformation" / f"{NOTEBOOK}.ipynb").write_bytes(b"\x00 not a notebook")
    url = server.create_database("class")
    results = grade_class(submitted, tmp / "out", GradeOptions(workers=1, timeout=30, db_url=url, seed=5, progress=False), CoursePaths(root))
    yield root, url, {(r["student_id"], r["notebook"]): r for r in results}
    shutil.rmtree(tmp, ignore_errors=True)



def test_grading_writes_every_score_into_the_postgresql_gradebook(server, graded, source_notebooks):
    _, url, results = graded
    scores = _scores(server, url)
    assert set(scores) == {(s, nb) for s in ("Ada_Lovelace", "bob") for nb in source_notebooks}
    ada = results[("Ada_Lovelace", NOTEBOOK)]
    assert ada["status"] == "graded" and ada["score"] == ada["max_score"] > 0
    assert scores[("Ada_Lovelace", NOTEBOOK)] == ada["max_score"]
    assert results[("bob", NOTEBOOK)]["status"] == "invalid"
    assert all(score == 0 for (sid, _), score in scores.items() if sid == "bob")


def test_nbgrader_export_reads_the_grades_from_postgresql(server, graded):
    root, url, results = graded
    export = root / "export.csv"
    run = subprocess.run(
        [str(BIN / "nbgrader"), "export", f"--CourseDirectory.root={root / 'assignments'}", f"--CourseDirectory.db_url={url}", f"--CsvExportPlugin.to={export}"],
        cwd=root / "assignments", capture_output=True, text=True, timeout=300,
        env=dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}"),
    )
    assert run.returncode == 0, run.stderr[-3000:]
    with open(export, newline="") as fh:
        rows = {r["student_id"]: r for r in csv.DictReader(fh)}
    assert set(rows) == {"Ada_Lovelace", "bob"}
    assert float(rows["Ada_Lovelace"]["score"]) == results[("Ada_Lovelace", NOTEBOOK)]["max_score"]
    assert float(rows["bob"]["score"]) == 0


def test_two_concurrent_grade_runs_on_one_database_lose_nothing(server, source_notebooks, make_course):
    # Two TAs grade two halves of a class at once. Students in both halves (who handed in
    # nothing: their rows are recorded within milliseconds) make both runs create the same
    # gradebook rows at the same moment; "shared" is graded by both.
    tmp = Path(tempfile.mkdtemp(prefix="dl-pgr-"))
    try:
        root = make_course(tmp)
        url = server.create_database("shared")
        both = tuple(f"s{i:02d}" for i in range(15))
        halves = {"A": ("a1", "a2"), "B": ("b1", "b2")}
        for half, students in halves.items():
            for sid in (*students, *both, "shared"):
                _submit(tmp / half, sid, source_notebooks[NOTEBOOK] if sid in ("a1", "b1", "shared") else None)
        runs = [
            subprocess.Popen(
                [str(BIN / "deformlab"), "--course", str(root), "grade", str(tmp / half), "--out", str(tmp / f"out-{half}"),
                 "--db", url, "--seed", "11", "--workers", "1", "--timeout", "30"],
                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                env=dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}"),
            )
            for half in halves
        ]
        for run in runs:
            _, err = run.communicate(timeout=600)
            assert run.returncode == 0, err[-3000:]
        scores = _scores(server, url)
        students = {s for half in halves.values() for s in half} | {*both, "shared"}
        assert set(scores) == {(s, nb) for s in students for nb in source_notebooks}
        full = {sid: scores[(sid, NOTEBOOK)] for sid in ("a1", "b1", "shared")}
        max_score = sum(
            float(r["max_score"]) for r in csv.DictReader(open(tmp / "out-A" / "grades.csv")) if r["student_id"] == "a1" and r["notebook"] == NOTEBOOK
        )
        assert full == {"a1": max_score, "b1": max_score, "shared": max_score} and max_score > 0
        # one row per student and per submission, whoever created it first
        assert server.query(url, "SELECT COUNT(*), COUNT(DISTINCT id) FROM student")[0] == (len(students), len(students))
        assert server.query(url, "SELECT COUNT(*) FROM submitted_assignment")[0][0] == len(students)
        for half, mine in halves.items():
            with open(tmp / f"out-{half}" / "grades.csv", newline="") as fh:
                rows = list(csv.DictReader(fh))
            assert {r["student_id"] for r in rows} >= {*mine, *both, "shared"}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def test_a_later_run_without_a_students_folder_keeps_that_students_grades(server, graded, make_course, source_notebooks):
    # Ada is in the gradebook's roster now; a run over another folder lists her with zeros in its
    # own grades.csv ("no submission folder") but must not write those zeros over her grades.
    root, url, results = graded
    tmp = Path(tempfile.mkdtemp(prefix="dl-pgl-"))
    try:
        _submit(tmp / "later", "carl", None)
        later = grade_class(tmp / "later", tmp / "out", GradeOptions(workers=1, db_url=url, seed=5, progress=False), CoursePaths(root))
        ada = {r["notebook"]: r for r in later if r["student_id"] == "Ada_Lovelace"}
        assert set(ada) == set(source_notebooks) and all(r["score"] == 0 and r["status"] == "missing" for r in ada.values())
        assert _scores(server, url)[("Ada_Lovelace", NOTEBOOK)] == results[("Ada_Lovelace", NOTEBOOK)]["max_score"]
        assert ("carl", NOTEBOOK) in _scores(server, url)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
