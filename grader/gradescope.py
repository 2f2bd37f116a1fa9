"""Gradescope: an autograder zip that runs this same grader on one submission.

Gradescope unpacks the zip in ``/autograder/source``, runs ``setup.sh`` once when
the image is built, and ``run_autograder`` per submission, with the student's
files in ``/autograder/submission``; the result goes to
``/autograder/results/results.json`` (one test per checked function).

    python -m grader.gradescope run --root /autograder

The zip's ``gradescope.json`` fixes the assignment's seed when the zip is built,
so every submission and every regrade meets the same hidden inputs; the seed is
recorded in each ``results.json``'s ``extra_data``. Grading refuses to run
without the bubblewrap sandbox unless the zip was built with
``--allow-unsandboxed``. ``run_autograder`` starts outside the course folder, so
the grader, the reference and the data are imported from the installed package
(which the sandbox hides from the student's kernel), never from the source tree.
"""

from __future__ import annotations

import argparse
import html
import json
import re
import secrets
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path

from grader.course_pack import default_assignment, is_bonus, packs
from grader.paths import course_paths

SETUP_SH = """#!/usr/bin/env bash
# Runs once when Gradescope builds the autograder image.
set -euo pipefail
SOURCE="${DEFORMLAB_SOURCE:-/autograder/source}"
if [ "${DEFORMLAB_SKIP_APT:-0}" != 1 ]; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3 python3-venv python3-dev bubblewrap libegl1 libgl1-mesa-dri
fi
PYTHON="${DEFORMLAB_PYTHON:-python3}"
if ! "$PYTHON" -c 'import sys; sys.exit(sys.version_info < (3, 11))'; then
  echo "DeformLab needs Python >= 3.11; this image has $("$PYTHON" --version 2>&1). Choose a newer base image in Gradescope's autograder settings (Ubuntu 24.04)." >&2
  exit 1
fi
cd "$SOURCE"
[ -x .venv/bin/python ] || "$PYTHON" -m venv .venv
.venv/bin/pip install -q -c constraints.txt .
# The installed starter package looks for data/ beside itself: a non-editable install needs its copy.
# (Asked from /, where `import starter` cannot mean this source tree's folder.)
INSTALLED="$(cd / && "$SOURCE/.venv/bin/python" -c 'import pathlib, starter; print(pathlib.Path(starter.__file__).resolve().parent.parent)')"
rm -rf "$INSTALLED/data" && cp -r data "$INSTALLED/data"
cd /
DEFORMLAB_ROOT="$SOURCE" "$SOURCE/.venv/bin/deformlab" build
"""

RUN_AUTOGRADER = """#!/usr/bin/env bash
# Runs once per submission, from outside the course folder (see grader/gradescope.py).
SOURCE="${DEFORMLAB_SOURCE:-/autograder/source}"
cd "$(dirname "$SOURCE")"
DEFORMLAB_ROOT="$SOURCE" exec "$SOURCE/.venv/bin/python" -m grader.gradescope run --root "$(dirname "$SOURCE")"
"""

CONFIG = "gradescope.json"

PACKAGED = ("reference", "grader", "starter", "data", "notebooks", "assignments/nbgrader_config.py", "pyproject.toml", "constraints.txt", "README.md")


def build_autograder_zip(target: Path, seed: int | None = None, assignment: str | None = None, allow_unsandboxed: bool = False) -> Path:
    """Write the autograder zip: the course (reference, grader, starter, data, notebooks), the two scripts, the config.

    Parameters
    ----------
    seed : int, optional
        The assignment's hidden-input seed (default: a fresh one); pass the same seed
        to rebuild a zip without changing anyone's hidden inputs.
    allow_unsandboxed : bool
        Grade even where bubblewrap cannot start (the student's code then runs unconfined).
    """
    paths = course_paths()
    assignment = assignment or default_assignment()
    seed = secrets.randbits(32) if seed is None else seed
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_name(target.name + ".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, text in (("setup.sh", SETUP_SH), ("run_autograder", RUN_AUTOGRADER)):
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o755 << 16  # executable, as Gradescope requires
            z.writestr(info, text)
        z.writestr(CONFIG, json.dumps({"assignment": assignment, "seed": seed, "allow_unsandboxed": allow_unsandboxed}, indent=1))
        # the course packs (their checks are hidden in the sandbox like the reference)
        pack_folders = [str(p.folder.relative_to(paths.root)) for p in packs().values() if p.folder.is_relative_to(paths.root)]
        for item in (*PACKAGED, *pack_folders):
            path = paths.root / item
            files = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
            for f in files:
                if "__pycache__" not in f.parts and not f.name.endswith(".pyc"):
                    z.write(f, str(f.relative_to(paths.root)))
    tmp.replace(target)
    return target


def results_json(unit_results: list[dict], seed: int | None = None, pictures_html: str = "") -> dict:
    """Gradescope's results format from the grader's unit results: one test per checked function.

    ``seed`` goes to ``extra_data``; ``pictures_html`` (the feedback pictures) is the top-level HTML output.
    """
    tests = []
    for r in sorted(unit_results, key=lambda r: r["notebook"]):
        for t in r["tests"]:
            lines = [t["summary"]]
            bonus = is_bonus(r["assignment"], r["notebook"])
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
        "output": pictures_html,
        "output_format": "html",
        "test_output_format": "text",
        "extra_data": {"seed": seed, "assignment": unit_results[0]["assignment"] if unit_results else None},
    }


_FIGURE = re.compile(r"<figure>.*?</figure>", re.S)


def pictures_html(feedback_folder: Path) -> str:
    """The labeled pictures of the feedback pages (our own escaped template output), one section per notebook."""
    parts = []
    for page in sorted(Path(feedback_folder).glob("*.html")):
        figures = _FIGURE.findall(page.read_text(encoding="utf-8"))
        if figures:
            parts.append(f"<h2>{html.escape(page.stem)}</h2>" + "".join(figures))
    return "\n".join(parts)


def read_config(root: Path) -> dict:
    """The zip's ``gradescope.json`` under ``root/source``.

    Raises
    ------
    ValueError
        If it is missing or unreadable.
    """
    path = Path(root) / "source" / CONFIG
    try:
        config = json.loads(path.read_text())
        int(config["seed"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ValueError(f"{path} is missing or unreadable ({exc}): build the autograder with `deformlab gradescope`") from None
    return config


class SandboxUnavailable(RuntimeError):
    """bubblewrap cannot start here and the zip does not allow grading without it."""


def run(root: Path) -> Path:
    """Grade ``root/submission`` and write ``root/results/results.json``.

    Raises
    ------
    SandboxUnavailable
        If bubblewrap cannot start and the zip was not built with ``--allow-unsandboxed``.
    """
    from grader.pipeline.run import GradeOptions, grade_class
    from grader.sandbox import bwrap_available

    root = Path(root)
    config = read_config(root)
    if not bwrap_available() and not config.get("allow_unsandboxed"):
        raise SandboxUnavailable(
            "bubblewrap cannot start a sandbox in this image, so the students' code would run unconfined: not grading. "
            "Install bubblewrap in setup.sh and allow user namespaces, or rebuild the zip with "
            "`deformlab gradescope --allow-unsandboxed` to accept the risk."
        )
    results_path = root / "results" / "results.json"
    results_path.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="dl-gs-") as tmp:
        assignment = config.get("assignment") or default_assignment()
        target = Path(tmp) / "submitted" / "submission" / assignment
        target.mkdir(parents=True)
        for nb in sorted((root / "submission").rglob("*.ipynb")):
            if ".ipynb_checkpoints" not in nb.parts:
                shutil.copy(nb, target / nb.name)
        results = grade_class(
            Path(tmp) / "submitted",
            Path(tmp) / "out",
            GradeOptions(db_url=f"sqlite:///{tmp}/gradebook.db", progress=False, autograded=Path(tmp) / "autograded",
                         seed=int(config["seed"]), assignment=assignment),
        )
        pictures = pictures_html(Path(tmp) / "out" / "feedback" / "submission")
    results_path.write_text(json.dumps(results_json(results, int(config["seed"]), pictures), indent=1))
    return results_path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m grader.gradescope")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="grade ROOT/submission into ROOT/results/results.json")
    p.add_argument("--root", default="/autograder")
    args = parser.parse_args(argv)
    try:
        print(f"wrote {run(Path(args.root))}")
    except (SandboxUnavailable, ValueError) as exc:
        print(f"DeformLab autograder: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
