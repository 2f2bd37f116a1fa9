"""Candidate pairs for the collusion pass from a sketch, so that exact comparison runs on few pairs.

Comparing every pair of a class is quadratic: 88 students x 8 notebooks took
331 s. The pass only reports pairs whose code similarity (copydetect's token
coverage of shared fingerprints, mean of both directions) reaches 0.7, or whose
identical wrong outputs weigh 2; this module finds a superset of those pairs in
time near-linear in the class:

- code: MinHash signatures of each student's set of winnowed fingerprint hashes
  (the same hashes copydetect compares), banded for locality-sensitive hashing.
  Two students sharing every row of one band are a candidate; a candidate whose
  signatures agree on fewer than ``MIN_JACCARD`` of their rows is dropped before
  the exact comparison. A pair at similarity 0.7 has a Jaccard index of its hash
  sets of at least about 0.4 (similarities ``c1 + c2 >= 1.4`` of the smaller and
  larger side give ``1 / (1/c1 + 1/c2 - 1) >= 0.4``; the corpus's lowest is
  0.37), and with ``BANDS`` bands of ``ROWS`` rows it is missed with probability
  ``(1 - J**ROWS)**BANDS``: 2e-6 at J = 0.37, 9e-4 at J = 0.3.
- identical wrong outputs: an inverted index of (hidden case, output digest).
  A shared output held by ``m`` students weighs ``1 / (m - 1)``; a student has at
  most ``L`` wrong outputs, so a pair that shares only outputs held by more than
  ``L / 2 + 1`` students weighs less than 2 and cannot be reported. Only the
  smaller groups are expanded into pairs, which is exact.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np

#: Rows per band and bands: 768 hash functions. Two rows made every pair of students who share one
#: function's method (J about 0.1) a candidate, quadratic in the class: at 10,000 synthetic students
#: the candidates did not fit the pass's 2 GiB. Three rows miss J = 0.37 with probability 2e-6.
ROWS, BANDS = 3, 256
#: Candidates whose signatures agree on fewer rows than this fraction are not compared exactly.
MIN_JACCARD = 0.2
#: Hashes processed at once when signing (bounds memory: this many x ROWS*BANDS x 8 bytes).
_CHUNK = 8192
_MASK = np.uint64(2**64 - 1)


def _mix(x: np.ndarray) -> np.ndarray:
    """splitmix64's finalizer: well-spread 64-bit values from copydetect's hashes (uint64, wraps)."""
    x = x.astype(np.uint64, copy=True)
    x ^= x >> np.uint64(30)
    x *= np.uint64(0xBF58476D1CE4E5B9)
    x ^= x >> np.uint64(27)
    x *= np.uint64(0x94D049BB133111EB)
    x ^= x >> np.uint64(31)
    return x


def signatures(sets: list[np.ndarray], num_perm: int = ROWS * BANDS, seed: int = 0) -> np.ndarray:
    """MinHash signatures of integer sets.

    Parameters
    ----------
    sets : list of (k_i,) int arrays
        One set of hashes per item (duplicates allowed).
    num_perm : int, optional
        Hash functions: ``h_j(x) = (a_j * mix(x) + b_j) >> 32`` over 64-bit words, ``a_j`` odd.
    seed : int, optional

    Returns
    -------
    (n, num_perm) uint64 array
        Row ``i`` holds the minimum of each hash function over ``sets[i]``; an empty set's row is all
        ``2**64 - 1`` (it matches nothing that is not empty: callers leave empty sets out).
    """
    rng = np.random.default_rng(seed)
    a = rng.integers(0, 2**63, num_perm, dtype=np.uint64) * np.uint64(2) + np.uint64(1)
    b = rng.integers(0, 2**63, num_perm, dtype=np.uint64)
    out = np.full((len(sets), num_perm), _MASK, dtype=np.uint64)
    sizes = np.array([len(s) for s in sets], dtype=np.int64)
    owners = np.repeat(np.arange(len(sets)), sizes)
    values = _mix(np.concatenate([np.asarray(s, dtype=np.int64) for s in sets]) if len(sets) else np.zeros(0, np.int64))
    # chunks of whole items, so that each item's minimum is taken in one reduceat
    start = 0
    while start < len(values):
        stop = min(len(values), start + _CHUNK)
        while stop < len(values) and owners[stop] == owners[stop - 1]:
            stop += 1
        hashed = (values[start:stop, None] * a[None, :] + b[None, :]) >> np.uint64(32)
        first = np.flatnonzero(np.r_[True, owners[start + 1:stop] != owners[start:stop - 1]])
        out[owners[start:stop][first]] = np.minimum.reduceat(hashed, first, axis=0)
        start = stop
    return out


def code_candidates(sets: list[np.ndarray], rows: int = ROWS, bands: int = BANDS,
                    min_jaccard: float = MIN_JACCARD, seed: int = 0) -> set[tuple[int, int]]:
    """Pairs ``(i, j)``, ``i < j``, of sets that may be similar: they share a band and an estimated Jaccard index.

    Parameters
    ----------
    sets : list of (k_i,) int arrays
        Fingerprint hashes per student; empty sets are never candidates.
    rows, bands : int, optional
        The banding (``ROWS``, ``BANDS``).
    min_jaccard : float, optional
        Candidates whose signatures agree on fewer than this fraction of hash functions are dropped.
    """
    keep = np.array([i for i, s in enumerate(sets) if len(s)], dtype=np.int64)
    if len(keep) < 2:
        return set()
    sig = signatures([sets[i] for i in keep], rows * bands, seed)
    found = []
    for band in range(bands):
        block = sig[:, band * rows:(band + 1) * rows]
        key = _mix(block[:, 0])
        for r in range(1, rows):
            key = _mix(key ^ block[:, r])
        order = np.argsort(key, kind="stable")
        sorted_key = key[order]
        starts = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1]])
        ends = np.r_[starts[1:], len(order)]
        for s, e in zip(starts[ends - starts > 1], ends[ends - starts > 1]):
            members = np.sort(order[s:e])
            i, j = np.triu_indices(len(members), 1)
            found.append(members[i] * len(keep) + members[j])
        if band % 16 == 15 and found:  # a pair is found in many bands: keep each once
            found = [np.unique(np.concatenate(found))]
    if not found:
        return set()
    codes = np.unique(np.concatenate(found))
    i, j = codes // len(keep), codes % len(keep)
    agree = np.empty(len(codes))
    for start in range(0, len(codes), 4096):  # bounded memory: 4096 pairs x 384 rows at once
        sl = slice(start, start + 4096)
        agree[sl] = (sig[i[sl]] == sig[j[sl]]).mean(axis=1)
    ok = agree >= min_jaccard
    return set(zip(keep[i[ok]].tolist(), keep[j[ok]].tolist()))


def wrong_output_candidates(wrong: dict[str, dict[str, str]], threshold: float) -> set[tuple[str, str]]:
    """Pairs of students ``(a, b)``, ``a < b``, whose identical wrong outputs may weigh ``threshold``.

    Parameters
    ----------
    wrong : dict
        Student id -> {hidden case label -> digest of their wrong output}.
    threshold : float
        The weight from which a pair is reported (each shared output held by ``m`` students weighs ``1/(m-1)``).

    Returns
    -------
    set of (str, str)
        Every pair that reaches ``threshold``, and others: the pairs that share an output held by at most
        ``L / threshold + 1`` students, ``L`` the most wrong outputs of one student (a pair sharing only
        more common outputs weighs less than ``L / (L / threshold) = threshold``).
    """
    holders: dict[tuple[str, str], list[str]] = defaultdict(list)
    for sid, cases in wrong.items():
        for label, digest in cases.items():
            if digest:
                holders[(label, digest)].append(sid)
    most = max((sum(1 for d in cases.values() if d) for cases in wrong.values()), default=0)
    largest = most / threshold + 1
    pairs = set()
    for group in holders.values():
        if 1 < len(group) <= largest:
            group = sorted(group)
            pairs.update((group[i], group[j]) for i in range(len(group)) for j in range(i + 1, len(group)))
    return pairs
