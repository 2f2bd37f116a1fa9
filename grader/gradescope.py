"""Gradescope: an autograder zip that runs this same grader on one submission.

Gradescope unpacks the zip in ``/autograder/source``, runs ``setup.sh`` once when
the image is built, and ``run_autograder`` per submission, with the student's
files in ``/autograder/submission``; the result goes to
``/autograder/results/results.json`` (one test per checked function).

    python -m grader.gradescope run --root /autograder
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path

from grader.contract import ASSIGNMENT, is_bonus
from grader.paths import course_paths

SETUP_SH = """#!/usr/bin/env bash
# Runs once when Gradescope builds the autograder image.
set -euo pipefail
apt-get update -qq
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv python3-dev bubblewrap libegl1 libgl1-mesa-dri
cd /autograder/source
python3 -m venv .venv
.venv/bin/pip install -q -c constraints.txt .
DEFORMLAB_ROOT=/autograder/source .venv/bin/deformlab build
"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Runs once per submission.
cd /autograder/source
DEFORMLAB_ROOT=/autograder/source exec .venv/bin/python -m grader.gradescope run --root /autograder
"""

PACKAGED = ("reference", "grader", "starter", "data", "notebooks", "assignments/nbgrader_config.py", "pyproject.toml", "constraints.txt", "README.md")


def build_autograder_zip(target: Path) -> Path:
    """Write the autograder zip: the course (reference, grader, starter, data, notebooks) plus the two scripts."""
    paths = course_paths()
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(target.name + ".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, text in (("setup.sh", SETUP_SH), ("run_autograder", RUN_AUTOGRADER)):
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o755 << 16  # executable, as Gradescope requires
            z.writestr(info, text)
        for item in PACKAGED:
            path = paths.root / item
            files = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
            for f in files:
                if "__pycache__" not in f.parts and not f.name.endswith(".pyc"):
                    z.write(f, str(f.relative_to(paths.root)))
    tmp.replace(target)
    return target


def results_json(unit_results: list[dict]) -> dict:
    """Gradescope's results format from the grader's unit results: one test per checked function."""
    tests = []
    for r in sorted(unit_results, key=lambda r: r["notebook"]):
        for t in r["tests"]:
            lines = [t["summary"]]
            bonus = is_bonus(r["notebook"])
            if bonus:
                lines.insert(0, f"bonus: up to {t['points']:g} extra points")
            lines += [f"- {c['label']}: {'passed' if c['passed'] else (c['error'] or '; '.join(c['failed']))}" for c in t["cases"]]
            tests.append(
                {
                    "name": f"{r['notebook']}{' (bonus)' if bonus else ''}: {t['function']}",
                    "score": t["score"],
                    # Gradescope's way to mark extra credit: points earned on a test worth 0.
                    "max_score": 0 if bonus else t["points"],
                    "output": "\n".join(lines + r.get("reasons", [])[:5]),
                    # Hidden inputs are the hidden tests: their details show once grades are published.
                    "visibility": "after_published",
                }
            )
    return {
        "score": round(sum(t["score"] for t in tests), 4),
        "tests": tests,
        "visibility": "after_published",
        "stdout_visibility": "hidden",
    }


def run(root: Path) -> Path:
    """Grade ``root/submission`` and write ``root/results/results.json``."""
    from grader.pipeline.run import GradeOptions, grade_class

    root = Path(root)
    results_path = root / "results" / "results.json"
    results_path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="dl-gs-") as tmp:
        target = Path(tmp) / "submitted" / "submission" / ASSIGNMENT
        target.mkdir(parents=True)
        for nb in sorted((root / "submission").rglob("*.ipynb")):
            if ".ipynb_checkpoints" not in nb.parts:
                shutil.copy(nb, target / nb.name)
        results = grade_class(
            Path(tmp) / "submitted",
            Path(tmp) / "out",
            GradeOptions(db_url=f"sqlite:///{tmp}/gradebook.db", progress=False, autograded=Path(tmp) / "autograded"),
        )
    results_path.write_text(json.dumps(results_json(results), indent=1))
    return results_path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m grader.gradescope")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="grade ROOT/submission into ROOT/results/results.json")
    p.add_argument("--root", default="/autograder")
    args = parser.parse_args(argv)
    print(f"wrote {run(Path(args.root))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
