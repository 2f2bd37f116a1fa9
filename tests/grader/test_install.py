"""A non-editable install (``pip install .``, as on a grading machine or a Dask worker).

The package is installed into a fresh virtual environment that borrows this
one's dependencies (a ``.pth`` file), so the test needs no network. Without a
checkout around the package, the course is found through configuration only.
"""

from __future__ import annotations

import os
import re
import shutil
import site
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def installed():
    tmp = Path(tempfile.mkdtemp(prefix="dl-install-"))
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(tmp / "venv")], check=True)
    python = tmp / "venv" / "bin" / "python"
    purelib = subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], capture_output=True, text=True, check=True).stdout.strip()
    Path(purelib, "borrowed.pth").write_text("\n".join(site.getsitepackages()) + "\n")
    # Build from a copy: the checkout must not end up on the new environment's path.
    src = tmp / "src"
    top_level = {".venv", ".git", "assignments", "dist", "build", "demo-out", "data", "notebooks", "tests"}
    shutil.copytree(ROOT, src, ignore=lambda folder, names: top_level & set(names) if Path(folder) == ROOT else {"__pycache__"} & set(names))
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--no-build-isolation", "--target", purelib, str(src)],
        check=True, capture_output=True, timeout=600,
    )
    shutil.rmtree(src)
    yield tmp, python
    shutil.rmtree(tmp, ignore_errors=True)


def _deformlab(python: Path, *args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    env = {k: v for k, v in (env or os.environ).items() if k != "DEFORMLAB_ROOT"}
    return subprocess.run([python, "-m", "grader.cli", *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=600)


def test_the_installed_package_is_not_the_checkout_and_tells_its_version(installed):
    tmp, python = installed
    where = subprocess.run([python, "-c", "import grader; print(grader.__file__)"], cwd=tmp, capture_output=True, text=True, check=True).stdout
    assert not where.startswith(str(ROOT))
    run = _deformlab(python, "--version", cwd=tmp)
    assert run.returncode == 0 and re.fullmatch(r"deformlab \d+\.\d+\.\d+\S*\n", run.stdout)


def test_without_a_setting_the_installed_kit_names_every_way_to_find_the_course(installed):
    tmp, python = installed
    run = _deformlab(python, "build", cwd=tmp)
    assert run.returncode == 2
    assert "--course" in run.stderr and "DEFORMLAB_ROOT" in run.stderr and "c.DeformLab.course_root" in run.stderr


def test_the_course_is_found_by_the_flag_and_by_the_course_nbgrader_config(installed, make_course):
    tmp, python = installed
    root = make_course(Path(tempfile.mkdtemp(prefix="dl-course-", dir=tmp)))
    shutil.rmtree(root / "assignments" / "source")
    by_flag = _deformlab(python, "--course", str(root), "build", cwd=tmp)
    assert by_flag.returncode == 0, by_flag.stderr
    assert len(list((root / "assignments" / "source" / "deformation").glob("*.ipynb"))) >= 7
    code = "from grader.paths import course_paths; print(course_paths().root)"
    from_config = subprocess.run([python, "-c", code], cwd=root / "assignments", capture_output=True, text=True,
                                 env={k: v for k, v in os.environ.items() if k != "DEFORMLAB_ROOT"})
    assert from_config.stdout.strip() == str(root.resolve()), from_config.stderr
    bad = _deformlab(python, "--course", str(tmp), "build", cwd=tmp)
    assert bad.returncode == 2 and "not a DeformLab course folder" in bad.stderr


def test_the_grader_core_installs_no_vtk_and_each_audience_has_an_extra(installed):
    tmp, python = installed
    code = "from importlib.metadata import requires; print('\\n'.join(requires('deformlab')))"
    requirements = subprocess.run([python, "-c", code], cwd=tmp, capture_output=True, text=True, check=True).stdout.splitlines()
    core = {re.split(r"[<>=\[ ;]", r)[0].lower() for r in requirements if "extra ==" not in r}
    assert not core & {"pyvista", "vtk", "jupyter", "jupyterlab", "ipywidgets", "ipyevents", "av"}
    assert {"numpy", "scipy", "libigl", "nbgrader", "nbclient"} <= core
    extras = {m.group(1) for r in requirements if (m := re.search(r'extra == "(\w+)"', r))}
    assert {"student", "demo", "postgres", "dask", "dev"} <= extras
