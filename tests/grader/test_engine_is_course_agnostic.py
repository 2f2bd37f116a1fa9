"""The engine (grader/) names no course and has no import cycle: courses live in their packs (assignments/<name>/)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

from grader.course_pack import packs

ROOT = Path(__file__).resolve().parents[2]
ENGINE = ROOT / "grader"


def _engine_files() -> list[Path]:
    return sorted(p for p in ENGINE.rglob("*") if p.suffix in (".py", ".j2", ".js", ".css") and "__pycache__" not in p.parts)


def test_no_engine_file_names_a_stage_or_a_graded_function_of_a_course():
    names = {n for course in packs().values() for n in (*course.functions, *course.stage_names) if "_" in n}
    assert len(names) > 40, "the deformation pack's names were not found"
    found = {}
    for path in _engine_files():
        text = path.read_text(encoding="utf-8")
        hits = sorted(n for n in names if re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", text))
        if hits:
            found[str(path.relative_to(ROOT))] = hits
    assert not found, f"engine files that name a course's stages or functions: {found}"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(modules: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> the engine modules it imports anywhere in its code (lazy imports inside functions too)."""
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                edges |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else []))
                edges.add(base)
                edges |= {f"{base}.{a.name}" for a in node.names}
        graph[name] = {e for e in edges if e in modules and e != name}
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_the_engine_has_no_import_cycle_not_even_through_lazy_imports():
    modules = {_module_name(p): p for p in ENGINE.rglob("*.py") if "__pycache__" not in p.parts}
    graph = _imports(modules)
    # a package's __init__ importing its own submodules is how a package is built, not a cycle between concerns
    for name in graph:
        graph[name] = {m for m in graph[name] if not (name.startswith(m + ".") and modules[m].name == "__init__.py")}
    assert _cycles(graph) == []
