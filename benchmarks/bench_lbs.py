"""Linear blend skinning in real time on the ~10k-vertex character, as the demo widget runs it.

The mesh is ``character_fine`` with its five bones, weighted by
``starter.skinning_widget.skinning_weights`` (normalized ``igl.bbw``) and
posed by forward kinematics (``starter.posing``). Three rates:

- LBS updates per second: ``U = M @ Tstack`` with the precomputed
  ``M = igl.lbs_matrix(V, W)`` and the poses' ``Tstack`` made beforehand; also
  with BLAS on one thread (``threadpoolctl``), since OpenBLAS threads on a small
  product can cost more than they gain on a loaded machine;
- pose updates per second: forward kinematics plus the product, a slider's work
  before the picture;
- rendered frames per second: ``SkinningWidget.set_pose`` for a sequence of
  poses, i.e. the sliders, LBS, the off-screen render (pyvista through EGL, or
  the matplotlib fallback) and the PNG bytes the widget sends to the browser;
- the same poses exported by ``SkinningWidget.export_animation`` as a GIF and
  (with PyAV installed) an MP4 at 20 frames/s: seconds and kilobytes of each.

The issue's target is at least 30 LBS updates per second.

Run with ``.venv/bin/python -m benchmarks.bench_lbs``.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from starter.meshes import load_handles, load_mesh
from starter.posing import CHARACTER_PARENTS, bone_joints, bone_transforms
from starter.skinning_widget import SkinningWidget, skinning_weights

MESH = "character_fine"
POSES = 2000
FRAMES = 120
TARGET = 30.0


def random_poses(count, bones, seed=0):
    """``(angles (count, bones), translations (count, 2))``: bones within ±60°, shifts within ±0.3."""
    rng = np.random.default_rng(seed)
    return rng.uniform(-np.pi / 3, np.pi / 3, size=(count, bones)), rng.uniform(-0.3, 0.3, size=(count, 2))


def _rate(run, count):
    """Calls per second of ``run(k)`` for ``k`` in ``range(count)`` (wall clock)."""
    start = time.perf_counter()
    for k in range(count):
        run(k)
    return count / (time.perf_counter() - start)


def main(poses=POSES, frames=FRAMES):
    """Time LBS alone, with forward kinematics, and with the widget's rendering; print the figures.

    Parameters
    ----------
    poses : int
        Poses timed for the LBS rates.
    frames : int
        Poses rendered through the widget.

    Returns
    -------
    dict
        ``vertices``, ``faces``, ``bones``, ``weights_s`` (BBW once),
        ``lbs_updates_per_s``, ``lbs_updates_per_s_one_blas_thread``,
        ``pose_updates_per_s``, ``rendered_frames_per_s``, ``render_backend``,
        ``png_kb`` (mean frame size), ``widget_label`` (the rates the widget
        itself reports over its last changes), ``gif_s``/``gif_kb`` and
        ``mp4_s``/``mp4_kb`` (the rendered poses exported; ``mp4_skipped``
        says why instead, without PyAV) and ``target_met`` (LBS updates per
        second ≥ 30).
    """
    V, F = load_mesh(MESH)
    bones = load_handles(MESH)["bones"]
    started = time.perf_counter()
    W = skinning_weights(V, F, bones)
    weights_s = time.perf_counter() - started

    widget = SkinningWidget(V, F, W, bones, CHARACTER_PARENTS)
    joints = bone_joints(V, bones)
    angles, shifts = random_poses(poses, len(bones))
    stacks = [bone_transforms(joints, a, CHARACTER_PARENTS, t).transpose(0, 2, 1).reshape(-1, 2)
              for a, t in zip(angles, shifts)]
    M = widget.M

    def product(k):
        return M @ stacks[k]

    def pose_update(k):
        return M @ bone_transforms(joints, angles[k], CHARACTER_PARENTS, shifts[k]).transpose(0, 2, 1).reshape(-1, 2)

    lbs = _rate(product, poses)
    with threadpool_limits(1):
        lbs_one = _rate(product, poses)
    pose = _rate(pose_update, poses)

    sizes = []

    def frame(k):
        widget.set_pose(angles[k], shifts[k])
        sizes.append(len(widget.image.value))

    widget.set_pose(angles[0], shifts[0])  # the first frame builds the off-screen scene
    rendered = _rate(frame, frames)
    exports = _exports(widget, angles[:frames], shifts[:frames])
    widget.renderer.close()

    figures = {
        "mesh": MESH,
        "vertices": len(V),
        "faces": len(F),
        "bones": len(bones),
        "weights_s": weights_s,
        "lbs_updates_per_s": lbs,
        "lbs_updates_per_s_one_blas_thread": lbs_one,
        "pose_updates_per_s": pose,
        "rendered_frames_per_s": rendered,
        "render_backend": widget.renderer.backend,
        "picture": f"{widget.renderer.size[0]}x{widget.renderer.size[1]}",
        "png_kb": float(np.mean(sizes)) / 1024,
        "widget_label": widget.label.value,
        **exports,
        "target_met": bool(lbs >= TARGET),
    }
    print(f"LBS on {MESH}: {len(V)} vertices, {len(F)} faces, {len(bones)} bones; BBW weights in {weights_s:.1f} s")
    print(f"M @ Tstack:                  {lbs:10,.0f} updates/s ({lbs_one:,.0f} with one BLAS thread; target >= {TARGET:.0f})")
    print(f"forward kinematics + M @ T:  {pose:10,.0f} updates/s")
    print(f"widget frames (LBS + {figures['render_backend']} render + PNG, {figures['picture']}): "
          f"{rendered:.1f} frames/s, {figures['png_kb']:.0f} kB per frame")
    print(f"the widget's label: {figures['widget_label']}")
    for kind in ("gif", "mp4"):
        if f"{kind}_kb" in figures:
            print(f"{frames} frames exported as {kind.upper()}: {figures[f'{kind}_s']:.2f} s, {figures[f'{kind}_kb']:.0f} kB")
        else:
            print(f"{kind.upper()} export not measured: {figures[f'{kind}_skipped']}")
    return figures


def _exports(widget, angles, shifts):
    """Seconds and kilobytes of the pose sequence as a GIF and an MP4 (20 frames/s)."""
    figures = {}
    with tempfile.TemporaryDirectory() as folder:
        for kind in ("gif", "mp4"):
            path = Path(folder) / f"poses.{kind}"
            started = time.perf_counter()
            try:
                widget.export_animation(path, angles, shifts, fps=20)
            except ImportError as error:  # PyAV is optional
                figures[f"{kind}_skipped"] = str(error)
                continue
            figures[f"{kind}_s"] = time.perf_counter() - started
            figures[f"{kind}_kb"] = path.stat().st_size / 1024
    return figures


if __name__ == "__main__":
    main()
