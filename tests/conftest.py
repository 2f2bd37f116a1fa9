"""Shared fixtures: the repository's paths and built instructor notebooks."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

os.environ.setdefault("DEFORMLAB_NO_PLOTS", "1")

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def source_notebooks(tmp_path_factory) -> dict[str, Path]:
    """The instructor notebooks, built from notebooks/ and reference/ into a temporary folder."""
    from grader.build.source_notebook import build_sources

    out = tmp_path_factory.mktemp("source")
    return {p.stem: p for p in build_sources(ROOT / "notebooks", out, "deformation")}
