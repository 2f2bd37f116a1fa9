"""The Gradescope zip on a simulated /autograder: setup.sh's steps with a non-editable install, then run_autograder.

Gradescope's image would download the dependencies; here the simulated image's
venv sees this environment's packages through hard links (same file system, so
the sandbox, which binds the venv, sees them too), without the editable install
of this checkout: grader, reference and starter come from ``pip install .``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import nbformat
import pytest

from tests.corpus import load_entry, student_notebook
from grader.gradescope import build_autograder_zip

pytestmark = [pytest.mark.slow, pytest.mark.timeout(900)]

OWN = ("__editable__", "deformlab", "grader", "reference", "starter", "__pycache__")


def image(tmp: Path) -> tuple[Path, dict]:
    """``/autograder`` with the zip unpacked in ``source/``, a prepared venv, and the environment for the scripts."""
    root = tmp / "autograder"
    source = root / "source"
    with zipfile.ZipFile(build_autograder_zip(tmp / "autograder.zip", seed=31337)) as z:
        z.extractall(source)
    for script in ("setup.sh", "run_autograder"):
        (source / script).chmod(0o755)
    subprocess.run([sys.executable, "-m", "venv", str(source / ".venv")], check=True)
    deps = source / ".venv" / "deps"
    deps.mkdir()
    for entry in Path(sysconfig.get_paths()["purelib"]).iterdir():
        if not entry.name.startswith(OWN):
            subprocess.run(["cp", "-al", str(entry), str(deps / entry.name)], check=True)
    site = next((source / ".venv" / "lib").glob("python3.*/site-packages"))
    (site / "deps.pth").write_text(f"{deps}\n")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("DEFORMLAB_", "PYTHONPATH"))}
    # pip builds the wheel in its usual isolated environment (setuptools from the package index, as on Gradescope).
    env |= {"DEFORMLAB_SOURCE": str(source), "DEFORMLAB_SKIP_APT": "1", "DEFORMLAB_PYTHON": sys.executable}
    return root, env


def test_setup_sh_refuses_a_python_older_than_3_11(tmp_path):
    source = tmp_path / "source"
    with zipfile.ZipFile(build_autograder_zip(tmp_path / "a.zip", seed=1)) as z:
        z.extract("setup.sh", source)
    old = tmp_path / "python3.10"
    old.write_text("#!/bin/sh\ncase \"$*\" in *--version*) echo 'Python 3.10.12';; *) exit 1;; esac\n")
    old.chmod(0o755)
    done = subprocess.run(["bash", str(source / "setup.sh")], capture_output=True, text=True,
                          env=os.environ | {"DEFORMLAB_SOURCE": str(source), "DEFORMLAB_SKIP_APT": "1", "DEFORMLAB_PYTHON": str(old)})
    assert done.returncode == 1
    assert "DeformLab needs Python >= 3.11; this image has Python 3.10.12" in done.stderr


def test_setup_and_run_autograder_grade_a_submission_with_a_non_editable_install(tmp_path, source_notebooks):
    root, env = image(tmp_path)
    source = root / "source"
    setup = subprocess.run(["bash", str(source / "setup.sh")], capture_output=True, text=True, env=env, cwd="/")
    assert setup.returncode == 0, setup.stderr[-3000:]
    installed = subprocess.run([str(source / ".venv" / "bin" / "python"), "-c", "import grader, starter; print(grader.__file__, starter.__file__)"],
                               capture_output=True, text=True, cwd="/", env=env)
    assert "site-packages" in installed.stdout and str(source / "grader") not in installed.stdout, installed.stdout
    (root / "submission").mkdir()
    # bbw forgets to normalize: the other functions earn every point, and bbw's failure comes with pictures
    buggy = load_entry(Path(__file__).resolve().parents[1] / "corpus" / "buggy" / "bbw_not_normalized.py")
    nb = student_notebook(nbformat.read(source_notebooks["04_bbw"], as_version=4), buggy.solutions)
    nbformat.write(nb, root / "submission" / "04_bbw.ipynb")
    run = subprocess.run([str(source / "run_autograder")], capture_output=True, text=True, env=env, cwd="/")
    assert run.returncode == 0, run.stderr[-3000:]
    results = json.loads((root / "results" / "results.json").read_text())
    bbw = [t for t in results["tests"] if t["name"].startswith("04_bbw")]
    lost = [t for t in bbw if t["score"] < t["max_score"]]
    assert bbw and all(t["max_score"] > 0 for t in bbw)
    assert len(lost) == 1 and lost[0]["name"].endswith("bbw"), [(t["name"], t["output"][:300]) for t in lost]
    assert "no DeformLab data folder found" not in json.dumps(results)
    assert results["extra_data"]["seed"] == 31337
    assert results["output_format"] == "html" and results["output"].count("<img ") >= 1 and " alt=" in results["output"], results["output"][:500]
    shutil.rmtree(root, ignore_errors=True)
