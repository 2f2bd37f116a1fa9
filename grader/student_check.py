"""Run a notebook's public tests and print one line per function (``deformlab check``).

This file is also shipped alone in the student bundle as ``check_notebook.py``,
so it imports only the standard library, nbformat and nbclient.
"""

from __future__ import annotations

import argparse
import os
import sys
import textwrap
from pathlib import Path


#: what the library policy's failures say (``starter.library_policy.message``)
POLICY_MARK = "library policy (LIBRARY_POLICY.md)"


def check_notebook(path: Path, timeout: float = 120.0) -> int:
    """Execute ``path`` top to bottom and report its public tests.

    Returns
    -------
    int
        0 when every tests cell passes, 1 otherwise (2 if the file cannot be read).
    """
    import nbformat
    from nbclient import NotebookClient

    path = Path(path)
    try:
        nb = nbformat.read(path, as_version=4)
    except Exception as exc:  # noqa: BLE001 - any unreadable file
        print(f"cannot read {path}: {exc}", file=sys.stderr)
        return 2
    os.environ.setdefault("DEFORMLAB_NO_PLOTS", "1")  # pictures are for the notebook, not for this table
    client = NotebookClient(nb, timeout=timeout, allow_errors=True, kernel_name="python3",
                            resources={"metadata": {"path": str(path.parent.resolve())}},
                            extra_arguments=["--IPKernelApp.log_level=ERROR"])  # no TCP-encryption notice per kernel
    try:
        client.execute()
    except Exception as exc:  # noqa: BLE001 - a timeout or a dead kernel ends the run, not the report
        print(f"note: execution stopped early: {type(exc).__name__}: {exc}", file=sys.stderr)
    rows = []
    for cell in nb.cells:
        meta = cell.get("metadata", {}).get("nbgrader") or {}
        gid = meta.get("grade_id", "")
        if cell.cell_type != "code" or not meta.get("grade") or not gid.startswith("test_"):
            continue
        error = next((o for o in cell.get("outputs", []) if o.get("output_type") == "error"), None)
        if cell.get("execution_count") is None and error is None:
            rows.append((gid[5:], "NOT RUN", "execution stopped before this cell"))
        elif error is None:
            rows.append((gid[5:], "pass", ""))
        else:
            rows.append((gid[5:], "FAIL", f"{error.get('ename')}: {error.get('evalue') or ''}"))
    width = max([len(r[0]) for r in rows] + [8])
    print(f"{'function':<{width}}  result   message")
    indent = " " * (width + 11)
    for name, status, message in rows:
        # The whole message: the public tests' hints span several lines.
        lines = [w for line in message.splitlines() for w in (textwrap.wrap(line, 100, subsequent_indent="  ") or [""])]
        print(f"{name:<{width}}  {status:<7}  {lines[0] if lines else ''}".rstrip())
        for line in lines[1:]:
            print(f"{indent}{line}".rstrip())
    failed = sum(status != "pass" for _, status, _ in rows)
    # the library policy's verdicts (starter/library_policy.py): the function scores 0 when graded
    banned = [name for name, status, message in rows if status == "FAIL" and POLICY_MARK in message]
    if banned:
        print(f"library policy: {', '.join(banned)} call{'s' if len(banned) == 1 else ''} a routine LIBRARY_POLICY.md "
              "does not allow there; graded, such a function scores 0")
    print(f"{len(rows) - failed} passed, {failed} failed")
    return 1 if failed or not rows else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python check_notebook.py",
        description="Run a notebook top to bottom and print, per function, whether its public tests pass. "
        "Passing them does not guarantee full marks: grading uses other, hidden inputs.",
    )
    parser.add_argument("notebook", help="the notebook to check, e.g. 00_warm_up.ipynb")
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds per cell (default: 120)")
    args = parser.parse_args(argv)
    return check_notebook(Path(args.notebook), timeout=args.timeout)


if __name__ == "__main__":
    sys.exit(main())
