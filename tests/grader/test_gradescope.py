"""The Gradescope autograder runs this grader on /autograder/submission (simulated in a folder)."""

import json
import stat
import zipfile

import nbformat

from tests.corpus import student_notebook
from grader.gradescope import build_autograder_zip, run


def test_the_zip_holds_executable_scripts_and_the_course(tmp_path):
    path = build_autograder_zip(tmp_path / "autograder.zip")
    with zipfile.ZipFile(path) as z:
        names = set(z.namelist())
        for script in ("setup.sh", "run_autograder"):
            assert stat.S_IMODE(z.getinfo(script).external_attr >> 16) & 0o111
        assert "-m grader.gradescope run --root" in z.read("run_autograder").decode()
        config = json.loads(z.read("gradescope.json"))
        assert config["assignment"] == "deformation" and isinstance(config["seed"], int) and config["allow_unsandboxed"] is False
    assert {"reference/arap.py", "grader/pipeline/run.py", "starter/plotting.py", "data/bar.npz"} <= names


def test_results_json_has_one_test_per_checked_function(tmp_path, source_notebooks):
    root = tmp_path / "autograder"
    (root / "submission").mkdir(parents=True)
    (root / "source").mkdir()
    (root / "source" / "gradescope.json").write_text(json.dumps({"assignment": "deformation", "seed": 4242}))
    nb = student_notebook(nbformat.read(source_notebooks["02_sign_correction"], as_version=4), {})
    nbformat.write(nb, root / "submission" / "02_sign_correction.ipynb")
    results = json.loads(run(root).read_text())
    tests = {t["name"]: t for t in results["tests"]}
    assert tests["02_sign_correction: optimal_rotation"]["score"] == tests["02_sign_correction: optimal_rotation"]["max_score"] > 0
    assert tests["03b_arap_global: arap_solve"]["score"] == 0, "a notebook not submitted earns nothing"
    bonus = tests["06_fast (bonus): fast_solve"]
    assert bonus["max_score"] == 0 and bonus["output"].startswith("bonus: up to"), "bonus points are Gradescope extra credit"
    assert all(t["visibility"] == "after_published" for t in results["tests"])
    assert results["score"] == sum(t["score"] for t in results["tests"])
    assert results["extra_data"] == {"seed": 4242, "assignment": "deformation"}, "a regrade can be reproduced"
    assert all(set(t) == {"name", "score", "max_score", "output", "visibility"} for t in results["tests"])


def test_the_same_zip_gives_every_run_the_same_seed(tmp_path):
    with zipfile.ZipFile(build_autograder_zip(tmp_path / "a.zip", seed=99)) as z:
        assert json.loads(z.read("gradescope.json"))["seed"] == 99


def test_grading_refuses_to_run_unconfined_unless_the_zip_allows_it(tmp_path, monkeypatch, capsys):
    import grader.sandbox
    from grader.gradescope import main

    monkeypatch.setattr(grader.sandbox, "bwrap_available", lambda: False)
    root = tmp_path / "autograder"
    (root / "source").mkdir(parents=True)
    (root / "submission").mkdir()
    (root / "source" / "gradescope.json").write_text(json.dumps({"assignment": "deformation", "seed": 1}))
    assert main(["run", "--root", str(root)]) == 1
    assert "would run unconfined: not grading" in capsys.readouterr().err
    assert not (root / "results" / "results.json").exists()


def test_a_root_without_the_zips_config_is_refused(tmp_path, capsys):
    from grader.gradescope import main

    assert main(["run", "--root", str(tmp_path)]) == 1
    assert "build the autograder with `deformlab gradescope`" in capsys.readouterr().err
