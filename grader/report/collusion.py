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
"""

from __future__ import annotations

import copy
import io
import itertools
from collections import defaultdict
from pathlib import Path

import nbformat

from grader.build.authored import BEGIN_SOLUTION, END_SOLUTION
from grader.pipeline.sanitize import SubmissionError, read_submission

#: copydetect's noise threshold (tokens) and winnowing window, its defaults for short code.
K, WINDOW = 15, 4
#: A pair is reported from this code similarity (mean of both directions) ...
SIMILARITY_THRESHOLD = 0.7
#: ... or from this much rarity-weighted identical wrong output.
WRONG_OUTPUT_THRESHOLD = 2.0
#: Characters of each side's code shown in the report.
MAX_SHOWN = 6000


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


def student_code(path: Path, shared: list[str]) -> str:
    """The solution cells of one submission that are the student's own (not verbatim boilerplate), joined."""
    try:
        cells = _solution_cells(read_submission(path))
    except SubmissionError:
        return ""
    plain = {text.strip() for text in shared}
    return "\n\n".join(text for _, text in sorted(cells.items()) if text.strip() and text.strip() not in plain)


def _fingerprint(code: str, shared_hashes):
    from copydetect import CodeFingerprint

    return CodeFingerprint("solution.py", K, WINDOW, boilerplate=shared_hashes, fp=io.StringIO(code))


def rank_pairs(codes: dict[str, str], shared: list[str], wrong: dict[str, dict[str, str]] | None = None,
               notebook: str = "", similarity_threshold: float = SIMILARITY_THRESHOLD) -> list[dict]:
    """Pairs of students above either threshold, strongest evidence first.

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
    """
    import numpy as np
    from copydetect import CodeFingerprint, compare_files

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
    pairs = []
    for a, b in itertools.combinations(sorted(set(prints) | set(wrong)), 2):
        similarity = 0.0
        if a in prints and b in prints:
            _, (s1, s2), _ = compare_files(prints[a], prints[b])
            similarity = float(s1 + s2) / 2
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


def class_collusion(results: list[dict], submitted: Path, sources: list[Path], assignment: str) -> list[dict]:
    """Ranked pairs of a graded class, every notebook, from its unit results and submissions."""
    from grader.pipeline.run import find_submission

    pairs = []
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
                codes[r["student_id"]] = student_code(path, shared)
            wrong[r["student_id"]] = {f"{t['function']}: {c['label']}": c["digest"]
                                      for t in r.get("tests", []) for c in t.get("cases", []) if c.get("digest")}
        pairs += rank_pairs(codes, shared, wrong, notebook)
    return sorted(pairs, key=lambda p: (-p["score"], p["notebook"], p["a"], p["b"]))
