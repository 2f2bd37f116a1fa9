"""Grading kernels, forked or fresh, have the library-call policy installed before the notebook's first cell."""

import json

import pytest

from grader.pipeline.unit import course_readonly
from grader.sandbox import SandboxedKernelManager, SandboxSpec
from grader.sandbox.bwrap import bwrap_available

pytestmark = pytest.mark.skipif(not bwrap_available(), reason="bubblewrap cannot create namespaces here")

# The notebook's first cell: it imports nothing of the policy, so what it finds was there before it.
FIRST_CELL = r"""
import sys, json
_policy = sys.modules.get("starter.library_policy")
import igl
from scipy.spatial.transform import Rotation
print(json.dumps({
    "loaded": _policy is not None,
    "installed": _policy is not None and _policy._state.installed,
    "namespace is the notebook's": _policy is not None and _policy._state.namespace is get_ipython().user_ns,
    "wrapped": [getattr(f, "__deformlab_routine__", None) for f in (igl.cotmatrix, igl.pyigl_core.cotmatrix, Rotation.from_matrix)],
}))
"""

SECOND_CELL = r"""
from igl import cotmatrix as _c
def cotangent_laplacian(V, F):
    return _c(V, F)
import numpy as np
_policy.reset(globals(), "cotangent_laplacian")
cotangent_laplacian(np.array([[0.0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]]))
print(json.dumps(_policy.violations("cotangent_laplacian")))
"""


def _first_cells(tmp_path, name: str) -> tuple[bool, list]:
    workdir = tmp_path / name
    workdir.mkdir()
    # as grading binds them: the course's data/ and starter/ (where a fresh kernel imports the policy from)
    spec = SandboxSpec(workdir=workdir, max_processes=64, readonly=course_readonly())
    km = SandboxedKernelManager(spec, runtime_root=tmp_path)
    km.start_kernel()
    kc = km.blocking_client()
    kc.start_channels()
    outputs = []
    try:
        kc.wait_for_ready(timeout=60)
        for code in (FIRST_CELL, SECOND_CELL):
            out = []
            reply = kc.execute_interactive(
                code, timeout=60, output_hook=lambda m: out.append(m["content"].get("text", "")) if m["msg_type"] == "stream" else None
            )
            assert reply["content"]["status"] == "ok", reply["content"]
            outputs.append(json.loads("".join(out)))
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    return km.forked, outputs


@pytest.mark.parametrize("template", ["on", "off"])
def test_the_policy_is_installed_before_the_first_cell_of_a_forked_and_of_a_fresh_kernel(tmp_path, monkeypatch, template):
    if template == "off":
        monkeypatch.setenv("DEFORMLAB_KERNEL_TEMPLATE", "off")
    forked, (first, second) = _first_cells(tmp_path, template)
    assert forked == (template == "on")
    routine = "scipy.spatial.transform.Rotation.from_matrix"
    assert first == {
        "loaded": True,
        "installed": True,
        "namespace is the notebook's": True,
        "wrapped": ["igl.cotmatrix", "igl.cotmatrix", routine],
    }
    assert second == ["igl.cotmatrix"]
