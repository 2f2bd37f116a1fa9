"""Collusion evidence for a TA to read, never a penalty: ranked pairs of students per notebook.

Two kinds of evidence, side by side:

- code similarity of the students' solution cells, by ``copydetect`` (winnowed
  fingerprints of normalized tokens, so renamed variables do not hide a copy),
  with the release stubs and the instructor's own solutions as boilerplate:
  code everybody was given, or code that is not the students' own, is no evidence;
- identical wrong outputs on the same hidden case: a run's students share the
  hidden inputs, so bit-identical wrong outputs (``digest`` per failed case in
  the unit results) most likely come from one piece of code. A wrong output that
  many students share is a common bug, so each shared output counts
  ``1 / (students with it - 1)``.

Only candidate pairs are compared exactly: those that a MinHash/LSH sketch of
the same fingerprints, or an inverted index of the wrong outputs, says may reach
a threshold (``grader.report.minhash``), so the pass grows near-linearly with the
class instead of with its number of pairs (``python -m benchmarks collusion``).

The pass reads every submission, so it is capped like the rest of the grader:
each student's own solution code per notebook is cut at ``MAX_CODE_BYTES`` (the
cut is evidence the report shows), and ``limited_collusion`` runs it in a child
process under ``CollusionCaps`` (address space, CPU time, wall clock), so that a
failure or a limit hit costs only the report's collusion section.
"""

from __future__ import annotations

import copy
import io
import itertools
import json
import os
import signal
import subprocess
import sys
from collections import defaultdict
from dataclasses import asdict, dataclass, field
from pathlib import Path

import nbformat
import numpy as np

from grader.build.authored import BEGIN_SOLUTION, END_SOLUTION
from grader.pipeline.read_submission import SubmissionError, read_submission

#: copydetect's noise threshold (tokens) and winnowing window, its defaults for short code.
K, WINDOW = 15, 4
#: A pair is reported from this code similarity (mean of both directions) ...
SIMILARITY_THRESHOLD = 0.7
#: ... or from this much rarity-weighted identical wrong output.
WRONG_OUTPUT_THRESHOLD = 2.0
#: The sketch is designed to find every pair from this code similarity on (a Jaccard index of about 0.4
#: and over, ``grader.report.minhash``); under it ``rank_pairs`` compares every pair.
SKETCH_FLOOR = 0.7
#: Characters of each side's code shown in the report.
MAX_SHOWN = 6000
#: Bytes (UTF-8) of one student's own solution code per notebook that the pass compares; the rest is cut
#: and the report names the cut. Honest solutions of a whole notebook are a few KiB; at this cap a
#: fingerprint costs about 0.3 CPU-s and a comparison 2 ms, whatever the code holds.
MAX_CODE_BYTES = 64 * 2**10


@dataclass(frozen=True)
class CollusionCaps:
    """The limits of the child process that runs the collusion pass (``limited_collusion``).

    Attributes
    ----------
    memory_bytes : int
        Address space the child may add to what it holds once started (``RLIMIT_AS``).
    cpu_seconds : float
        CPU time of the pass, whatever the class: the budget is this ...
    cpu_seconds_per_submission : float
        ... plus this per submission compared (reading a notebook at the submission size cap and
        fingerprinting its capped code) ...
    cpu_seconds_per_pair : float
        ... plus this per pair of submissions of one notebook (a comparison of two capped codes).
    max_code_bytes : int or None
        ``MAX_CODE_BYTES``; ``None`` compares code uncut.
    """

    memory_bytes: int = 2 * 2**30
    cpu_seconds: float = 60.0
    cpu_seconds_per_submission: float = 1.0
    cpu_seconds_per_pair: float = 0.005
    max_code_bytes: int | None = MAX_CODE_BYTES

    def cpu_budget(self, students_per_notebook: list[int]) -> int:
        """Whole CPU-seconds allowed for a class with these numbers of compared submissions per notebook."""
        pairs = sum(n * (n - 1) // 2 for n in students_per_notebook)
        return int(self.cpu_seconds + self.cpu_seconds_per_submission * sum(students_per_notebook)
                   + self.cpu_seconds_per_pair * pairs) + 1

    def wall_seconds(self, cpu_budget: int) -> float:
        """Wall-clock time the child may take: its CPU budget three times over (a busy machine) and a minute."""
        return 3.0 * cpu_budget + 60.0


@dataclass
class CollusionEvidence:
    """What the collusion pass found, for the report.

    Attributes
    ----------
    pairs : list of dict
        Ranked pairs (``rank_pairs``), strongest evidence first.
    cuts : list of dict
        ``student_id, notebook, bytes, cap``: whose own code was cut at ``cap`` bytes (of ``bytes``).
    missing : str or None
        Why the pass produced no evidence (a limit hit, a failure); ``None`` when it ran.
    cpu_seconds, peak_rss_bytes : float or None
        What the pass cost in its child process, when it ran there.
    """

    pairs: list[dict] = field(default_factory=list)
    cuts: list[dict] = field(default_factory=list)
    missing: str | None = None
    cpu_seconds: float | None = None
    peak_rss_bytes: int | None = None

    def summary(self) -> str:
        """One line for the TA's terminal."""
        if self.missing:
            return f"no collusion evidence: {self.missing}"
        cut = f"; {len(self.cuts)} submission(s) cut at the code cap" if self.cuts else ""
        return f"{len(self.pairs)} pair(s) with collusion evidence{cut}"


def _solution_cells(nb) -> dict[str, str]:
    cells = {}
    for cell in nb.cells:
        meta = cell.get("metadata", {}).get("nbgrader") or {}
        gid = meta.get("grade_id")
        if cell.get("cell_type") == "code" and meta.get("solution") and isinstance(gid, str):
            cells[gid] = cell.source
    return cells


def boilerplate(source: nbformat.NotebookNode) -> list[str]:
    """Code that is no evidence: the release stubs and the instructor's solutions of ``source``."""
    from nbgrader.preprocessors import ClearSolutions

    stubs, _ = ClearSolutions().preprocess(copy.deepcopy(source), {})
    # The instructor's solutions as they would read without nbgrader's markers.
    solutions = ["\n".join(line for line in text.splitlines() if line.strip() not in (BEGIN_SOLUTION, END_SOLUTION))
                 for text in _solution_cells(source).values()]
    return [*_solution_cells(stubs).values(), *solutions]


def cap_code(code: str, max_bytes: int | None = MAX_CODE_BYTES) -> tuple[str, int | None]:
    """``code`` cut at ``max_bytes`` UTF-8 bytes (never inside a character), and its full size if it was cut.

    Returns
    -------
    (str, int or None)
        The code compared, and ``len(code.encode())`` when that is over the cap (else ``None``).
    """
    if max_bytes is None or len(code) * 4 <= max_bytes:  # a character is at most 4 bytes: no need to encode
        return code, None
    data = code.encode("utf-8", "surrogatepass")
    if len(data) <= max_bytes:
        return code, None
    return data[:max_bytes].decode("utf-8", "ignore"), len(data)


def student_code(path: Path, shared: list[str]) -> str:
    """The solution cells of one submission that are the student's own (not verbatim boilerplate), joined."""
    try:
        cells = _solution_cells(read_submission(path))
    except SubmissionError:
        return ""
    plain = {text.strip() for text in shared}
    return "\n\n".join(text for _, text in sorted(cells.items()) if text.strip() and text.strip() not in plain)


@dataclass
class _Fingerprint:
    """A copydetect ``CodeFingerprint`` kept as two arrays, and ``_similarity`` of two of them.

    A whole ``CodeFingerprint`` keeps the raw and filtered code, a per-token offset table and a
    dict of lists per hash: about 245 KiB per student on a notebook of ten functions, so a class of 10,000 did not fit
    the pass's memory cap. These arrays take 8 bytes per occurrence and 8 per distinct hash.

    Attributes
    ----------
    unique : (u,) numpy.ndarray of int64
        The winnowed k-gram hashes that are not boilerplate, sorted, without repeats.
    which : (h,) numpy.ndarray of int32
        One per occurrence of a hash: its index in ``unique``.
    positions : (h,) numpy.ndarray of int32
        Where each occurrence is in the filtered code.
    token_coverage : int
        Tokens of the filtered code that some winnowed hash covers (copydetect's denominator).
    empty : bool
        The filtered code is empty.
    """

    unique: np.ndarray
    which: np.ndarray
    positions: np.ndarray
    token_coverage: int
    empty: bool


def _fingerprint(code: str, shared_hashes) -> _Fingerprint:
    from copydetect import CodeFingerprint

    full = CodeFingerprint("solution.py", K, WINDOW, boilerplate=shared_hashes, fp=io.StringIO(code))
    counts = [len(where) for where in full.hash_idx.values()]
    unique, which = np.unique(np.repeat(np.array(list(full.hash_idx), dtype=np.int64), counts), return_inverse=True)
    positions = np.array([i for where in full.hash_idx.values() for i in where], dtype=np.int32)
    return _Fingerprint(unique, which.astype(np.int32), positions, int(full.token_coverage), not len(full.filtered_code))


def _similarity(a: _Fingerprint, b: _Fingerprint) -> float:
    """copydetect's ``compare_files`` similarity of ``a`` and ``b``, the mean of both directions.

    Each side: the tokens covered by the occurrences of the hashes both share, over its token coverage.
    """
    from copydetect.utils import get_copied_slices

    common = np.intersect1d(a.unique, b.unique, assume_unique=True)
    if not common.size:
        return 0.0
    total = 0.0
    for side in (a, b):
        shared = np.isin(side.unique, common, assume_unique=True)[side.which]
        slices = get_copied_slices(side.positions[shared].astype(np.int64), K)
        if not side.empty:
            total += float(np.sum(slices[1] - slices[0])) / side.token_coverage
    return total / 2

def candidate_pairs(prints: dict, wrong: dict[str, dict[str, str]]) -> list[tuple[str, str]]:
    """Pairs that may reach either threshold, from sketches (``grader.report.minhash``), sorted.

    Parameters
    ----------
    prints : dict
        Student id -> ``_fingerprint``.
    wrong : dict
        Student id -> {hidden case label -> digest of their wrong output}.
    """
    from grader.report.minhash import code_candidates, wrong_output_candidates

    ids = sorted(prints)
    pairs = {(ids[i], ids[j]) for i, j in code_candidates([prints[sid].unique for sid in ids])}
    return sorted(pairs | wrong_output_candidates(wrong, WRONG_OUTPUT_THRESHOLD))


def rank_pairs(codes: dict[str, str], shared: list[str], wrong: dict[str, dict[str, str]] | None = None,
               notebook: str = "", similarity_threshold: float = SIMILARITY_THRESHOLD,
               exhaustive: bool = False) -> list[dict]:
    """Pairs of students above either threshold, strongest evidence first.

    Only candidate pairs (``candidate_pairs``: a sketch, near-linear in the class) are compared
    exactly, unless ``exhaustive`` or a ``similarity_threshold`` under ``SKETCH_FLOOR``, which
    compare every pair.

    Parameters
    ----------
    codes : dict
        Student id -> their own solution code (``student_code``).
    shared : list of str
        Boilerplate code (``boilerplate``).
    wrong : dict, optional
        Student id -> {hidden case label -> digest of their wrong output}.
    similarity_threshold : float, optional
        Code similarity from which a pair is reported (0 reports every pair).
    exhaustive : bool, optional
        Compare every pair (quadratic), as the pass did before the sketch; for tests and benchmarks.
    """
    from copydetect import CodeFingerprint

    # As copydetect's own detector does: every k-gram of the boilerplate (window 1), not only the winnowed ones.
    hashes = []
    for text in shared:
        hashes.extend(CodeFingerprint("boilerplate.py", K, 1, fp=io.StringIO(text)).hashes)
    shared_hashes = np.unique(np.array(hashes, dtype=np.int64))
    prints = {sid: _fingerprint(code, shared_hashes) for sid, code in codes.items() if code.strip()}
    wrong = wrong or {}
    holders: dict[tuple[str, str], int] = defaultdict(int)
    for cases in wrong.values():
        for label, digest in cases.items():
            holders[(label, digest)] += 1
    if exhaustive or similarity_threshold < SKETCH_FLOOR:
        compared = itertools.combinations(sorted(set(prints) | set(wrong)), 2)
    else:
        compared = candidate_pairs(prints, wrong)
    pairs = []
    for a, b in compared:
        similarity = 0.0
        if a in prints and b in prints:
            similarity = _similarity(prints[a], prints[b])
        same = sorted(label for label, d in wrong.get(a, {}).items() if d and wrong.get(b, {}).get(label) == d)
        weight = sum(1.0 / (holders[(label, wrong[a][label])] - 1) for label in same)
        if similarity >= similarity_threshold or weight >= WRONG_OUTPUT_THRESHOLD:
            pairs.append({
                "a": a, "b": b, "notebook": notebook, "similarity": round(similarity, 3),
                "shared_wrong": same, "wrong_weight": round(weight, 3),
                "score": round(similarity + weight / (weight + 2), 3),
                "code_a": codes.get(a, "")[:MAX_SHOWN], "code_b": codes.get(b, "")[:MAX_SHOWN],
            })
    return sorted(pairs, key=lambda p: (-p["score"], p["a"], p["b"]))


def class_collusion(results: list[dict], submitted: Path, sources: list[Path], assignment: str,
                    max_code_bytes: int | None = MAX_CODE_BYTES) -> CollusionEvidence:
    """Ranked pairs of a graded class, every notebook, from its unit results and submissions, in this process.

    Parameters
    ----------
    results : list of dict
        The run's unit results (``grader.report.class_report.load_results``).
    submitted : Path
        The SUBMITTED folder that was graded.
    sources : list of Path
        The instructor notebooks.
    max_code_bytes : int or None, optional
        Each student's own code per notebook is cut there (``MAX_CODE_BYTES``); the cuts are in the evidence.
    """
    from grader.pipeline.plan import find_submission

    evidence = CollusionEvidence()
    for source_path in sources:
        source = nbformat.read(source_path, as_version=4)
        shared = boilerplate(source)
        notebook = source_path.stem
        codes, wrong = {}, {}
        for r in results:
            if r["notebook"] != notebook or r["status"] not in ("graded", "graded-with-incidents"):
                continue
            path, _ = find_submission(Path(submitted) / r["student_id"] / assignment, notebook)
            if path is not None:
                codes[r["student_id"]], full = cap_code(student_code(path, shared), max_code_bytes)
                if full is not None:
                    evidence.cuts.append({"student_id": r["student_id"], "notebook": notebook, "bytes": full, "cap": max_code_bytes})
            wrong[r["student_id"]] = {f"{t['function']}: {c['label']}": c["digest"]
                                      for t in r.get("tests", []) for c in t.get("cases", []) if c.get("digest")}
        evidence.pairs += rank_pairs(codes, shared, wrong, notebook)
    evidence.pairs.sort(key=lambda p: (-p["score"], p["notebook"], p["a"], p["b"]))
    evidence.cuts.sort(key=lambda c: (c["notebook"], c["student_id"]))
    return evidence


def _compared_per_notebook(results: list[dict]) -> list[int]:
    counts: dict[str, int] = defaultdict(int)
    for r in results:
        if r["status"] in ("graded", "graded-with-incidents"):
            counts[r["notebook"]] += 1
    return list(counts.values())


#: The child's exit status when Python ran out of its address space (``MemoryError``).
_OUT_OF_MEMORY = 3


def limited_collusion(results: list[dict], submitted: Path, sources: list[Path], assignment: str,
                      caps: CollusionCaps = CollusionCaps()) -> CollusionEvidence:
    """``class_collusion`` in a child process under ``caps``: a failure costs only the collusion evidence.

    The child (``python -m grader.report.collusion``) reads the submissions, so it
    runs with an address-space cap, a CPU-time cap that grows with the class
    (``CollusionCaps.cpu_budget``) and a wall-clock cap; past any of them, or if it
    fails, the evidence is empty and ``missing`` says why. Nothing the child does
    reaches the grades.

    Returns
    -------
    CollusionEvidence
        With the child's CPU time and peak resident memory when it finished.
    """
    cpu = caps.cpu_budget(_compared_per_notebook(results))
    wall = caps.wall_seconds(cpu)
    # what class_collusion reads of each result, no more
    slim = [{"student_id": r["student_id"], "notebook": r["notebook"], "status": r["status"],
             "tests": [{"function": t["function"], "cases": [{"label": c["label"], "digest": c.get("digest")} for c in t.get("cases", [])]}
                       for t in r.get("tests", [])]} for r in results]
    job = {"results": slim, "submitted": str(submitted), "sources": [str(p) for p in sources], "assignment": assignment,
           "memory_bytes": caps.memory_bytes, "cpu_seconds": cpu, "max_code_bytes": caps.max_code_bytes}
    # One BLAS thread: the pass does no linear algebra, and each thread would reserve address space.
    # A fixed PYTHONHASHSEED: copydetect hashes k-grams with Python's hash(), so the same class gets the same report.
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1", PYTHONHASHSEED="0")
    child = subprocess.Popen([sys.executable, "-m", "grader.report.collusion"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, env=env)
    try:
        out, err = child.communicate(json.dumps(job).encode(), timeout=wall)
    except subprocess.TimeoutExpired:
        child.kill()
        child.communicate()
        return CollusionEvidence(missing=f"the collusion pass took longer than its wall-clock cap of {wall:.0f} s and was stopped")
    code = child.returncode
    if code == 0:
        found = json.loads(out)
        return CollusionEvidence(pairs=found["pairs"], cuts=found["cuts"], cpu_seconds=found["cpu_seconds"],
                                 peak_rss_bytes=found["peak_rss_bytes"])
    if code == _OUT_OF_MEMORY:
        why = f"needed more than its memory cap ({caps.memory_bytes / 2**30:g} GiB of address space)"
    elif code in (-signal.SIGXCPU, -signal.SIGKILL):
        why = f"ran past its CPU cap ({cpu} CPU-s for this class)" if code == -signal.SIGXCPU else "was killed (SIGKILL)"
    elif code < 0:
        why = f"was killed by signal {signal.Signals(-code).name}"
    else:
        last = err.decode("utf-8", "replace").strip().splitlines()[-1:] or ["no message"]
        # the message may quote a submission's path: nothing unprintable reaches the TA's terminal
        why = f"failed (exit status {code}: {''.join(ch if ch.isprintable() else '?' for ch in last[0][:300])})"
    return CollusionEvidence(missing=f"the collusion pass {why}")


def _child(job: dict) -> dict:
    """The child's work: limits first, then ``class_collusion``; what it cost goes with the evidence."""
    import resource

    from grader.sandbox.limits import status_bytes

    now = status_bytes(os.getpid(), "VmSize") or 0
    resource.setrlimit(resource.RLIMIT_AS, (now + job["memory_bytes"],) * 2)
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    # SIGXCPU at the budget; SIGKILL a few seconds later if it were caught
    resource.setrlimit(resource.RLIMIT_CPU, (job["cpu_seconds"], job["cpu_seconds"] + 5))
    evidence = class_collusion(job["results"], Path(job["submitted"]), [Path(p) for p in job["sources"]], job["assignment"],
                               job["max_code_bytes"])
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return asdict(evidence) | {"cpu_seconds": round(usage.ru_utime + usage.ru_stime, 3),
                               "peak_rss_bytes": status_bytes(os.getpid(), "VmHWM")}


def _main() -> int:
    job = json.loads(sys.stdin.buffer.read())
    real_stdout, sys.stdout = sys.stdout, sys.stderr  # only the answer goes to stdout
    try:
        answer = json.dumps(_child(job))
    except MemoryError:
        return _OUT_OF_MEMORY
    real_stdout.write(answer)
    real_stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(_main())
