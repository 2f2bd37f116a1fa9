"""The sketch (MinHash/LSH, an inverted index of wrong outputs) finds the same ranked pairs as comparing every pair."""

import random
from pathlib import Path

import nbformat
import numpy as np
import pytest

from tests.corpus import build_submission, load_corpus, load_entry
from grader.report.collusion import WRONG_OUTPUT_THRESHOLD, boilerplate, rank_pairs, student_code
from grader.report.minhash import code_candidates, signatures, wrong_output_candidates

from .conftest import ROOT, rename_variables

INDEPENDENT = ROOT / "tests" / "report" / "independent"


def class_of(notebook, source_notebooks, tmp_path):
    """Every corpus entry (correct, buggy) and independent submission of ``notebook``, and renamed copies of every
    fifth independent one (a buggy entry's own code is its one changed line: a copy of it is no evidence)."""
    source = nbformat.read(source_notebooks[notebook], as_version=4)
    shared = boilerplate(source)
    entries = [e for e in load_corpus(ROOT / "tests" / "corpus") if e.kind in ("buggy", "correct") and e.edit is None
               and e.notebook == notebook and (e.source or e.notebook) == notebook]
    entries += [load_entry(p, kind="correct") for p in sorted((INDEPENDENT / notebook).glob("*.py"))]
    codes, planted = {}, set()
    for k, entry in enumerate(entries):
        sid = f"{k:02d}_{entry.name}"
        path = build_submission(entry, source_notebooks[notebook].parent, tmp_path, sid)
        codes[sid] = student_code(path, shared)
        if entry.path.parent.parent == INDEPENDENT and k % 5 == 0:
            copy = tmp_path / f"copy_{sid}.ipynb"
            nbformat.write(rename_variables(nbformat.read(path, as_version=4), {"V": "verts", "F": "tris", "P": "pts", "S": "cov"}), copy)
            codes[f"copy_{sid}"] = student_code(copy, shared)
            planted.add(tuple(sorted((sid, f"copy_{sid}"))))
    return codes, shared, planted


@pytest.mark.parametrize("notebook", ["01_shape_matching", "03_arap"])
def test_the_sketch_ranks_the_same_pairs_as_every_pair_compared(notebook, source_notebooks, tmp_path):
    codes, shared, planted = class_of(notebook, source_notebooks, tmp_path)
    # wrong outputs: a rare one shared by a pair, a common one by everybody
    ids = sorted(codes)
    wrong = {sid: {"f: common": "c0"} for sid in ids}
    for label in ("f: a", "f: b"):
        wrong[ids[1]][label] = wrong[ids[7]][label] = "rare"
    exact = rank_pairs(codes, shared, wrong, notebook, exhaustive=True)
    sketched = rank_pairs(codes, shared, wrong, notebook)
    assert [(p["a"], p["b"], p["score"]) for p in sketched] == [(p["a"], p["b"], p["score"]) for p in exact]
    assert planted <= {(p["a"], p["b"]) for p in sketched}
    assert (ids[1], ids[7]) in {(p["a"], p["b"]) for p in sketched}


def test_minhash_agreement_estimates_the_jaccard_index():
    rng = np.random.default_rng(1)
    base = rng.integers(-2**62, 2**62, 400)
    for overlap in (0, 100, 200, 300, 400):
        other = np.concatenate([base[:overlap], rng.integers(-2**62, 2**62, 400 - overlap)])
        jaccard = overlap / (800 - overlap)
        sig = signatures([base, other])
        assert abs((sig[0] == sig[1]).mean() - jaccard) < 0.1


def test_sets_with_the_jaccard_index_of_a_pair_at_the_threshold_are_candidates_and_disjoint_sets_are_not():
    rng = np.random.default_rng(2)
    sets = []
    for _ in range(30):  # 30 pairs at J = 0.37 (162 shared of 438), the lowest of a pair at similarity 0.7 in the corpus
        shared = rng.integers(-2**62, 2**62, 162)
        sets += [np.concatenate([shared, rng.integers(-2**62, 2**62, 138)]), np.concatenate([shared, rng.integers(-2**62, 2**62, 138)])]
    found = code_candidates(sets[:60] + [rng.integers(-2**62, 2**62, 300) for _ in range(60)])
    assert {(2 * k, 2 * k + 1) for k in range(30)} <= found
    assert not {p for p in found if p[1] >= 60}, "disjoint sets are never candidates"


def test_every_pair_whose_wrong_outputs_reach_the_threshold_is_a_candidate():
    rng = random.Random(3)
    # common bugs: each case's wrong output one of three; three pairs share rarer outputs on a few cases
    wrong = {f"s{k:02d}": {f"case {c}": f"d{rng.randrange(3)}" for c in range(rng.randint(1, 8))} for k in range(40)}
    for k, shared in ((0, 2), (2, 3), (4, 5)):
        for c in range(shared):
            wrong[f"s{k:02d}"][f"case {c}"] = wrong[f"s{k + 1:02d}"][f"case {c}"] = f"rare {k}"
    wrong["s06"]["case 0"] = wrong["s07"]["case 0"] = wrong["s08"]["case 0"] = "three"
    holders = {}
    for cases in wrong.values():
        for item in cases.items():
            holders[item] = holders.get(item, 0) + 1
    reach = {(a, b) for a in wrong for b in wrong if a < b
             and sum(1 / (holders[(l, d)] - 1) for l, d in wrong[a].items() if wrong[b].get(l) == d) >= WRONG_OUTPUT_THRESHOLD}
    found = wrong_output_candidates(wrong, WRONG_OUTPUT_THRESHOLD)
    assert {("s00", "s01"), ("s02", "s03"), ("s04", "s05")} <= reach <= found
    assert ("s06", "s07") in found, "an output held by three students may still add up to the threshold"
    assert len(found) < 40 * 39 // 2 / 4, "outputs held by many students are not expanded into pairs"


def test_the_compact_fingerprint_gives_copydetects_similarity(source_notebooks, tmp_path):
    import io
    import itertools

    from copydetect import CodeFingerprint, compare_files

    from grader.report.collusion import K, WINDOW, _fingerprint, _similarity

    codes, shared, _ = class_of("03_arap", source_notebooks, tmp_path)
    codes = dict(sorted(codes.items())[:24])
    shared_hashes = np.unique(np.array([h for text in shared for h in CodeFingerprint("b.py", K, 1, fp=io.StringIO(text)).hashes], dtype=np.int64))
    full = {sid: CodeFingerprint("s.py", K, WINDOW, boilerplate=shared_hashes, fp=io.StringIO(code)) for sid, code in codes.items()}
    compact = {sid: _fingerprint(code, shared_hashes) for sid, code in codes.items()}
    checked = 0
    for a, b in itertools.combinations(sorted(codes), 2):
        _, (s1, s2), _ = compare_files(full[a], full[b])
        assert _similarity(compact[a], compact[b]) == pytest.approx(float(s1 + s2) / 2, abs=1e-12)
        checked += float(s1 + s2) > 0
    assert checked > 50
