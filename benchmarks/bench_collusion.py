"""The collusion pass at 100, 1,000 and 10,000 synthetic students: time, peak memory, planted copies found.

Synthetic students are written from the corpus's styles: for each function of a
notebook, a student takes the solution of one corpus entry (``tests/corpus``
correct and buggy entries, ``tests/report/independent``), then rewrites it as a
student writing on their own would (``restyle``: new identifiers, operands of
``+`` and ``*`` in their own order, a result named before it is returned,
helper definitions in their own order, their own comments). One student in 50
hands in a copy of another's notebook with renamed identifiers and new comments
(planted copies). Wrong outputs on hidden cases are the ones of the buggy
entries a student's styles came from: common bugs, so shared by many.

The figures are the report's (``limited_collusion``: the child process that the
class report runs): wall time, CPU time and peak resident memory, the pairs
reported, and how many planted copies rank among them. At 100 students the
sketch's pairs are also checked against the exhaustive pass (every pair).

    python -m benchmarks collusion
    DEFORMLAB_BENCH_COLLUSION_SIZES=100,1000 python -m benchmarks.bench_collusion
"""

from __future__ import annotations

import ast
import builtins
import hashlib
import os
import random
import shutil
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import nbformat

from grader.build.source_notebook import build_sources
from tests.corpus import load_corpus, load_entry, student_notebook
from grader.report.collusion import boilerplate, limited_collusion, rank_pairs, student_code

ROOT = Path(__file__).resolve().parents[1]
#: The course pack whose notebooks the synthetic class writes.
ASSIGNMENT = "deformation"
#: The notebook with the most functions and styles (10 functions: its four and the six it copies from 02 and
#: 03; 30-33 styles each). 01_shape_matching's one-line functions leave too few distinct students: at 1,000
#: students, 503 pairs of synthetic students who drew the same styles passed the threshold, a quadratic
#: number that is no copying.
NOTEBOOKS = ("03b_arap_global",)
SIZES = (100, 1000, 10000)
COPY_RATE = 50
WORDS = ("pts", "verts", "tris", "acc", "mat", "tmp", "rot", "vals", "idx", "cur", "out", "res", "w", "src", "dst", "cov",
         "left", "right", "center", "data", "vec", "arr", "buf", "item", "part", "edge", "face", "corner")


def styles(notebook: str) -> dict[str, list[tuple[str, str]]]:
    """Function -> [(entry name, its solution)], every correct or buggy corpus entry and independent submission."""
    entries = [e for e in load_corpus(ROOT / "tests" / "corpus") if e.kind in ("buggy", "correct") and e.edit is None]
    entries += [load_entry(p, kind="correct") for p in sorted((ROOT / "tests" / "report" / "independent" / notebook).glob("*.py"))]
    pool: dict[str, list[tuple[str, str]]] = defaultdict(list)
    for e in entries:
        if e.notebook == notebook and (e.source or e.notebook) == notebook and "@@" not in "".join(e.solutions.values()):
            for function, text in e.solutions.items():
                pool[function].append((f"{e.kind}/{e.name}", text))
    return pool


class _Restyle(ast.NodeTransformer):
    """One student's habits: their own names, operand order, named results."""

    def __init__(self, rng: random.Random, keep: set[str]):
        self.rng, self.keep, self.names = rng, keep, {}

    def _name(self, old: str) -> str:
        if old in self.keep or old.startswith("__"):
            return old
        if old not in self.names:
            self.names[old] = f"{self.rng.choice(WORDS)}_{len(self.names)}"
        return self.names[old]

    def visit_Name(self, node):
        node.id = self._name(node.id)
        return node

    def visit_arg(self, node):
        node.arg = self._name(node.arg)
        return node

    def visit_BinOp(self, node):
        self.generic_visit(node)
        if isinstance(node.op, (ast.Add, ast.Mult)) and self.rng.random() < 0.5:
            node.left, node.right = node.right, node.left
        if isinstance(node.op, ast.MatMult) and self.rng.random() < 0.5:  # a @ b as np.dot(a, b)
            return ast.Call(func=ast.Attribute(value=ast.Name(id="np", ctx=ast.Load()), attr="dot", ctx=ast.Load()),
                            args=[node.left, node.right], keywords=[])
        if isinstance(node.op, ast.Pow) and isinstance(node.right, ast.Constant) and node.right.value == 2 and self.rng.random() < 0.5:
            return ast.BinOp(left=node.left, op=ast.Mult(), right=node.left)
        return node

    def visit_Call(self, node):
        self.generic_visit(node)
        f = node.func  # np.sum(x, ...) <-> x.sum(...)
        if (isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id == "np" and node.args
                and f.attr in ("sum", "mean", "max", "min") and self.rng.random() < 0.5):
            return ast.Call(func=ast.Attribute(value=node.args[0], attr=f.attr, ctx=ast.Load()), args=node.args[1:],
                            keywords=node.keywords)
        return node

    def _named(self, stmt):
        """``stmt`` with some of its sub-expressions named first, as a student who writes in steps would."""
        pre = []
        if isinstance(stmt, (ast.Assign, ast.Return, ast.AugAssign)) and stmt.value is not None:
            stmt.value = self._steps(stmt.value, pre, top=True)
        return [*pre, stmt]

    def _steps(self, expr, pre, top=False):
        if isinstance(expr, (ast.Lambda, ast.ListComp, ast.SetComp, ast.DictComp, ast.GeneratorExp, ast.IfExp, ast.Starred)):
            return expr  # names bound inside stay inside
        for field, value in ast.iter_fields(expr):
            if isinstance(value, ast.expr) and not isinstance(expr, ast.Attribute):
                setattr(expr, field, self._steps(value, pre))
            elif isinstance(value, list):
                setattr(expr, field, [self._steps(v, pre) if isinstance(v, ast.expr) else v for v in value])
        if not top and isinstance(expr, (ast.Call, ast.BinOp, ast.Subscript)) and isinstance(getattr(expr, "ctx", ast.Load()), ast.Load) \
                and self.rng.random() < 0.4:
            tmp = self._name(f"step_{len(self.names)}")
            pre.append(ast.Assign(targets=[ast.Name(id=tmp, ctx=ast.Store())], value=expr))
            return ast.Name(id=tmp, ctx=ast.Load())
        return expr

    def visit_FunctionDef(self, node):
        self.generic_visit(node)
        docstring = node.body[:1] if ast.get_docstring(node) is not None else []
        node.body = node.body[len(docstring):]
        body = list(docstring)
        if self.rng.random() < 0.5:  # inputs made arrays first
            for a in node.args.args[:self.rng.randint(1, 2)]:
                body.append(ast.Assign(targets=[ast.Name(id=a.arg, ctx=ast.Store())], value=ast.Call(
                    func=ast.Attribute(value=ast.Name(id="np", ctx=ast.Load()), attr="asarray", ctx=ast.Load()),
                    args=[ast.Name(id=a.arg, ctx=ast.Load())], keywords=[ast.keyword(arg="dtype", value=ast.Name(id="float", ctx=ast.Load()))])))
        for stmt in [s for stmt in node.body for s in self._named(stmt)]:
            if isinstance(stmt, ast.Return) and stmt.value is not None and self.rng.random() < 0.5:
                name = ast.Name(id=self._name(f"result_{len(self.names)}"), ctx=ast.Store())
                body += [ast.Assign(targets=[name], value=stmt.value), ast.Return(value=ast.Name(id=name.id, ctx=ast.Load()))]
            else:
                body.append(stmt)
        node.body = body
        return node


def restyle(code: str, rng: random.Random) -> str:
    """``code`` as another student would write it: same method, their own names, order and comments."""
    tree = ast.parse(code)
    # module-level names (imports, the contract's functions) and builtins keep their names
    keep = {a.asname or a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
    keep |= {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    keep |= set(dir(builtins)) | {"np", "sp", "scipy", "igl", "numpy"}
    tree = _Restyle(rng, keep).visit(tree)
    defs = [n for n in tree.body if isinstance(n, ast.FunctionDef)]
    if len(defs) > 1:  # helpers in the student's own order
        slots = [i for i, n in enumerate(tree.body) if isinstance(n, ast.FunctionDef)]
        rng.shuffle(defs)
        for i, d in zip(slots, defs):
            tree.body[i] = d
    lines = ast.unparse(ast.fix_missing_locations(tree)).splitlines()
    for _ in range(rng.randint(0, 3)):
        lines.insert(rng.randint(0, len(lines)), f"# note {rng.randint(0, 10**6)}: {rng.choice(WORDS)}")
    return "\n".join(lines)


def _digest(*parts) -> str:
    return hashlib.sha256("/".join(map(str, parts)).encode()).hexdigest()[:16]


def synthetic_class(n: int, sources: dict[str, Path], submitted: Path, seed: int = 0) -> tuple[list[dict], set]:
    """Write ``n`` students' notebooks under ``submitted``; their unit results and the planted (copy, original) pairs."""
    rng = random.Random(seed)
    results, planted, written = [], set(), {}
    pools = {nb: styles(nb) for nb in NOTEBOOKS}
    source_nbs = {nb: nbformat.read(sources[nb], as_version=4) for nb in NOTEBOOKS}
    for k in range(n):
        sid = f"s{k:05d}"
        original = f"s{rng.randrange(k):05d}" if k % COPY_RATE == COPY_RATE - 1 else None
        if original:
            planted.add((min(sid, original), max(sid, original)))
        for nb in NOTEBOOKS:
            if original:  # the copy: the original's code, renamed and recommented, and its outputs
                solutions = {f: restyle_copy(text, rng) for f, text in written[(original, nb)][0].items()}
                wrong = written[(original, nb)][1]
            else:
                solutions, wrong = {}, {}
                for function, pool in sorted(pools[nb].items()):
                    name, text = rng.choice(pool)
                    solutions[function] = restyle(text, rng)
                    if name.startswith("buggy/"):
                        wrong |= {f"{function}: case {c}": _digest(name, function, c) for c in range(rng.randint(2, 6))}
            written[(sid, nb)] = (solutions, wrong)
            folder = submitted / sid / ASSIGNMENT
            folder.mkdir(parents=True, exist_ok=True)
            nbformat.write(student_notebook(source_nbs[nb], solutions), folder / f"{nb}.ipynb")
            tests = defaultdict(list)
            for label, d in wrong.items():
                tests[label.split(":")[0]].append({"label": label.split(": ", 1)[1], "digest": d})
            results.append({"student_id": sid, "notebook": nb, "status": "graded",
                            "tests": [{"function": f, "cases": cases} for f, cases in tests.items()]})
    return results, planted


def restyle_copy(code: str, rng: random.Random) -> str:
    """A copy disguised: every identifier renamed, comments changed; the statements as they were."""
    tree = ast.parse(code)
    keep = {a.asname or a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
    keep |= {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))} | set(dir(builtins))
    renamer = _Restyle(rng, keep)
    renamer.visit_BinOp = lambda node: renamer.generic_visit(node)  # operand order kept
    renamer.visit_FunctionDef = lambda node: renamer.generic_visit(node)
    lines = ast.unparse(renamer.visit(tree)).splitlines()
    lines.insert(0, f"# my own work ({rng.randint(0, 10**6)})")
    return "\n".join(lines)


def run(n: int, sources: dict[str, Path], work: Path, check_exhaustive: bool) -> dict:
    submitted = work / f"submitted-{n}"
    t0 = time.perf_counter()
    results, planted = synthetic_class(n, sources, submitted)
    made = time.perf_counter() - t0
    t0 = time.perf_counter()
    evidence = limited_collusion(results, submitted, [sources[nb] for nb in NOTEBOOKS], ASSIGNMENT)
    wall = time.perf_counter() - t0
    if evidence.missing:
        raise RuntimeError(f"{n} students: {evidence.missing}")
    found = {(p["a"], p["b"]) for p in evidence.pairs}
    figures = {f"{n} students: report wall time (s)": round(wall, 2),
               f"{n} students: report CPU time (s)": evidence.cpu_seconds,
               f"{n} students: report peak memory (MiB)": round(evidence.peak_rss_bytes / 2**20, 1),
               f"{n} students: pairs reported": len(evidence.pairs),
               f"{n} students: planted copies found": f"{len(planted & found)} of {len(planted)}",
               f"{n} students: pairs reported that were not planted": len(found - planted),
               f"{n} students: time to write the class (s)": round(made, 1)}
    if check_exhaustive:  # in this process: copydetect's hashes are Python's, salted per process
        same = True
        for nb in NOTEBOOKS:
            source = nbformat.read(sources[nb], as_version=4)
            shared = boilerplate(source)
            codes = {r["student_id"]: student_code(submitted / r["student_id"] / ASSIGNMENT / f"{nb}.ipynb", shared)
                     for r in results if r["notebook"] == nb}
            wrong = {r["student_id"]: {f"{t['function']}: {c['label']}": c["digest"] for t in r["tests"] for c in t["cases"]}
                     for r in results if r["notebook"] == nb}
            t0 = time.perf_counter()
            exact = rank_pairs(codes, shared, wrong, nb, exhaustive=True)
            figures[f"{n} students: exhaustive pass of {nb}, in process (s)"] = round(time.perf_counter() - t0, 2)
            t0 = time.perf_counter()
            sketched = rank_pairs(codes, shared, wrong, nb)
            figures[f"{n} students: sketched pass of {nb}, in process (s)"] = round(time.perf_counter() - t0, 2)
            same &= [(p["a"], p["b"], p["score"]) for p in exact] == [(p["a"], p["b"], p["score"]) for p in sketched]
        figures[f"{n} students: same ranked pairs as the exhaustive pass"] = same
    shutil.rmtree(submitted, ignore_errors=True)
    for k, v in figures.items():
        print(f"{k}: {v}", flush=True)
    return figures


def main() -> dict:
    sizes = [int(s) for s in os.environ.get("DEFORMLAB_BENCH_COLLUSION_SIZES", ",".join(map(str, SIZES))).split(",")]
    work = Path(tempfile.mkdtemp(prefix="dl-bench-collusion-"))
    try:
        sources = {p.stem: p for p in build_sources(work / "source", ASSIGNMENT)}
        figures: dict = {"notebooks": ", ".join(NOTEBOOKS)}
        for n in sizes:
            figures |= run(n, sources, work, check_exhaustive=n <= 100)
        # CPU time is the steadier figure on a shared machine; wall time is printed beside it
        for kind in ("CPU", "wall"):
            times = [(n, figures[f"{n} students: report {kind} time (s)"]) for n in sizes]
            for (n0, t0), (n1, t1) in zip(times, times[1:]):
                figures[f"growth {n0} -> {n1} students: report {kind} time ratio"] = round(t1 / t0, 2)
                print(f"growth {n0} -> {n1} students (x{n1 / n0:g}): report {kind} time x{t1 / t0:.2f}", flush=True)
        return figures
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
