# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Demo · Interactive skinning (libigl's demo 403)
#
# Not graded: run it, play with it. The lecture ended with libigl's tutorial
# example 403: pose a character by its handles and watch linear blend skinning
# (LBS) with bounded biharmonic weights (BBW) follow in real time. This
# notebook is that experience for the 2D character of stages 04 and 05, at its
# fine resolution (about 10,000 vertices):
#
# 1. bounded biharmonic weights for the five bones, computed once;
# 2. a widget: drag a bone's tip with the mouse and the bone turns to follow
#    it, drag the hips and the whole character moves; sliders do the same
#    with numbers, and every change re-evaluates LBS and redraws;
# 3. a scripted animation, saved as an animated GIF for your notes;
# 4. the measured frame rate.
#
# **How the dragging works.** libigl's viewer draws the mesh with OpenGL in
# its own window and picks handles under the mouse. Here the kernel renders
# every frame off screen (pyvista through EGL, or matplotlib where OpenGL is
# missing) into an image widget; `ipyevents` sends the mouse's presses and
# moves over that image back to the kernel, which finds the handle under the
# mouse from the fixed view, turns or moves it, and redraws. (pyvista's
# `trame` backend would stream a live 3D view instead, but it needs its own
# web server beside Jupyter; for a 2D character an image is all it takes.)
# Mouse and sliders respond while the kernel runs: in an exported HTML page
# they do nothing.

# %%
import time

import numpy as np
from IPython.display import Image, display

from starter import load_handles, load_mesh, plotting
from starter.posing import CHARACTER_PARENTS, bone_joints, bone_transforms
from starter.shapes import character_2d_skeleton
from starter.skinning_widget import SkinningWidget, skinning_weights

V, F = load_mesh("character_fine")
bones = load_handles("character_fine")["bones"]
bone_names = character_2d_skeleton()["bone_names"]
print(f"character_fine: {len(V):,} vertices, {len(F):,} triangles; bones: {', '.join(bone_names)}")

# %% [markdown]
# ## 1 · Weights
#
# Every vertex on a bone is constrained to weight 1 for its bone and 0 for the
# others; bounded biharmonic weights fill in the rest (stage 04). Your stage 04
# `bbw` lives in your own notebook, so this demo calls libigl's `igl.bbw`,
# which solves the same problem but returns weights whose rows do not sum to
# one exactly: `skinning_weights` clips them to $[0, 1]$ and divides every
# row by its sum, as your `bbw` does. This is the slow part (a few seconds); it
# runs once per kernel.

# %%
started = time.perf_counter()
W = skinning_weights(V, F, bones)
print(f"weights {W.shape} in {time.perf_counter() - started:.1f} s: all within [0, 1]: {bool(((W >= 0) & (W <= 1)).all())}, "
      f"rows sum to 1 within {np.abs(W.sum(axis=1) - 1).max():.1e}")
plotting.show_weights(V, F, W, handles=bones)

# %% [markdown]
# ## 2 · Pose it
#
# A pose is one rotation angle per bone. The bones form a small hierarchy
# (`CHARACTER_PARENTS`): the arms hang on the spine, so turning the spine
# carries the arms along, while the legs turn on their own about the hips.
# `starter.posing.bone_transforms` turns the angles into one rigid transform
# per bone (*forward kinematics*), and the widget computes
#
# $$U = M\,T_{\text{stack}}, \qquad M = \texttt{lbs\_matrix}(V, W)\ \text{(computed once)},$$
#
# on every change: a single $n \times 3m$ by $3m \times 2$ product.
# The colours blend one colour per bone with the weights, the dark segments
# are the posed bones, and the line below the sliders reports the measured
# rates: LBS updates per second, and frames per second with the picture drawn
# and sent to the browser.
#
# **Try it:** press near the end of a dark segment (a bone's tip) and drag:
# the bone turns about its joint to point at the mouse, and the bones hanging
# on it follow. Press near the hips (where the spine and legs start) and drag
# to move the character. The sliders follow the mouse, whole degrees and
# centimetres at a time.

# %%
demo = SkinningWidget(V, F, W, bones, CHARACTER_PARENTS, names=bone_names)
demo

# %% [markdown]
# ## 3 · A scripted animation
#
# The same widget poses the character from code: here a wave with a little
# bounce, one period in 40 frames, saved as a looping GIF (the sliders stay
# where you left them). A name ending in `.mp4` writes an H.264 video instead,
# smaller and smoother for slides; it needs PyAV (`pip install av`), whose
# wheel brings its own FFmpeg.

# %%
phase = 2 * np.pi * np.arange(40) / 40
angles = np.column_stack([
    0.15 * np.sin(phase),            # spine sways
    -0.6 - 0.6 * np.sin(phase),      # left arm waves
    0.4 * np.sin(2 * phase),         # right arm
    -0.25 * np.sin(phase),           # left leg
    0.25 * np.sin(phase),            # right leg
])
translations = np.column_stack([np.zeros_like(phase), 0.05 * np.abs(np.sin(phase))])
gif = demo.export_animation("demo_skinning.gif", angles, translations, fps=20)
print(f"wrote {gif} ({gif.stat().st_size / 1024:.0f} kB, {len(angles)} frames)")
display(Image(filename=str(gif)))

# %% [markdown]
# ## 4 · Is it real time?
#
# The cell below moves the widget through 60 random poses exactly as slider
# changes do, then times the product $M\,T_{\text{stack}}$ alone. Real time
# means at least 30 updates per second; the product alone runs thousands of
# times faster than the eye needs, and what limits the frame rate is drawing
# the picture, not skinning.

# %%
rng = np.random.default_rng(0)
for a, t in zip(rng.uniform(-1.0, 1.0, (60, len(bones))), rng.uniform(-0.3, 0.3, (60, 2))):
    demo.set_pose(a, t)
rates = demo.frame_rates()

joints = bone_joints(V, bones)
stacks = [bone_transforms(joints, a, CHARACTER_PARENTS).transpose(0, 2, 1).reshape(-1, 2)
          for a in rng.uniform(-1.0, 1.0, (500, len(bones)))]
started = time.perf_counter()
for stack in stacks:
    U = demo.M @ stack
product_rate = len(stacks) / (time.perf_counter() - started)

print(f"through the widget: {rates['lbs_updates_per_second']:,.0f} LBS updates/s, "
      f"{rates['rendered_frames_per_second']:.1f} rendered frames/s ({demo.renderer.backend})")
print(f"M @ Tstack alone: {product_rate:,.0f} updates/s on {len(V):,} vertices "
      f"({'meets' if product_rate >= 30 else 'misses'} the 30 updates/s target)")
demo.set_pose(np.zeros(len(bones)))
