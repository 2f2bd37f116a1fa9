"""Lift a reference function into the source of a notebook solution cell.

The reference is the one source of truth: the instructor notebook's solution cell
is the function's own source, preceded by exactly the imports it uses, with its
body wrapped in nbgrader's solution markers so the release keeps the signature
and the docstring only.
"""

from __future__ import annotations

import ast
import builtins
import inspect
import textwrap
from dataclasses import dataclass

from grader.contract import CONTRACT_NAMES, reference_function

BEGIN_SOLUTION = "### BEGIN SOLUTION"
END_SOLUTION = "### END SOLUTION"


class LiftError(ValueError):
    """A reference function breaks the rules that let it be lifted (CONTRIBUTING.md)."""


@dataclass(frozen=True)
class LiftedFunction:
    """A contract function ready to become a solution cell.

    Attributes
    ----------
    name : str
    imports : tuple of str
        Import statements the body needs, in module order.
    calls : frozenset of str
        Other contract functions the body uses (they need earlier solution cells).
    source : str
        The cell source: imports, a blank line, the function with its body between
        the solution markers.
    body : str
        The dedented body alone (what must never reach a release).
    """

    name: str
    imports: tuple[str, ...]
    calls: frozenset[str]
    source: str
    body: str


def _module_imports(module_source: str) -> dict[str, str]:
    """Map each name bound by a top-level import of a module to its import statement."""
    bound: dict[str, str] = {}
    for node in ast.parse(module_source).body:
        if isinstance(node, ast.Import):
            for alias in node.names:
                name = alias.asname or alias.name.split(".")[0]
                stmt = f"import {alias.name}" + (f" as {alias.asname}" if alias.asname else "")
                bound[name] = stmt
        elif isinstance(node, ast.ImportFrom) and node.module != "__future__":
            for alias in node.names:
                stmt = f"from {'.' * node.level}{node.module or ''} import {alias.name}"
                bound[alias.asname or alias.name] = stmt + (f" as {alias.asname}" if alias.asname else "")
    return bound


def _free_names(func: ast.FunctionDef) -> set[str]:
    """Names a function reads that it does not bind itself (a conservative approximation)."""
    loaded: set[str] = set()
    bound: set[str] = set()
    for node in ast.walk(func):
        if isinstance(node, ast.Name):
            (loaded if isinstance(node.ctx, ast.Load) else bound).add(node.id)
        elif isinstance(node, ast.arg):
            bound.add(node.arg)
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node is not func:
            bound.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            bound.update((a.asname or a.name.split(".")[0]) for a in node.names)
        elif isinstance(node, ast.ExceptHandler) and node.name:
            bound.add(node.name)
    # Decorators and annotations are not part of the lifted code's behaviour.
    return loaded - bound - set(dir(builtins))


def lift(name: str) -> LiftedFunction:
    """Build the solution cell of contract function ``name`` from ``reference/``.

    Raises
    ------
    LiftError
        If the function uses a module-level name that is neither an import nor a
        contract function, or has decorators.
    """
    fn = reference_function(name)
    module = inspect.getmodule(fn)
    source = textwrap.dedent(inspect.getsource(fn))
    tree = ast.parse(source)
    func = tree.body[0]
    if not isinstance(func, ast.FunctionDef) or func.name != name:
        raise LiftError(f"reference.{module.__name__}.{name} is not a plain function definition")
    if func.decorator_list:
        raise LiftError(f"{module.__name__}.{name} has decorators; lifted functions cannot")

    imports_of = _module_imports(inspect.getsource(module))
    calls, needed = set(), []
    for free in sorted(_free_names(func)):
        if free in CONTRACT_NAMES:
            calls.add(free)
        elif free in imports_of:
            needed.append(imports_of[free])
        else:
            raise LiftError(
                f"{module.__name__}.{name} uses {free!r}, which is neither an import nor a "
                "contract function: lifted functions may not use module-level helpers (CONTRIBUTING.md)"
            )
    order = list(imports_of.values())
    imports = tuple(sorted(set(needed), key=order.index))

    lines = source.splitlines()
    first = func.body[0]
    has_doc = isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str)
    if has_doc and len(func.body) == 1:
        raise LiftError(f"{module.__name__}.{name} has no body besides its docstring")
    body_start = (first.end_lineno if has_doc else func.body[0].lineno - 1)  # 0-based index of first body line
    header, body_lines = lines[:body_start], lines[body_start:]
    while body_lines and not body_lines[0].strip():
        body_lines.pop(0)
    indent = " " * (len(body_lines[0]) - len(body_lines[0].lstrip()))
    cell = "\n".join(
        [*imports, "", "", *header, indent + BEGIN_SOLUTION, *body_lines, indent + END_SOLUTION]
    ).lstrip("\n")
    return LiftedFunction(
        name=name,
        imports=imports,
        calls=frozenset(calls),
        source=cell,
        body=textwrap.dedent("\n".join(body_lines)),
    )
