"""Interactive linear blend skinning in a notebook: libigl's demo 403 with the mouse and sliders.

A 2D character with bone handles is skinned with bounded biharmonic weights
and posed by forward kinematics (:mod:`starter.posing`); every slider change
recomputes the deformed mesh as one product ``U = M @ Tstack`` with the
precomputed ``M = lbs_matrix(V, W)`` and renders it off screen into an image.

- :func:`skinning_weights`: bounded biharmonic weights with rows summing to one;
- :class:`SkinRenderer`: off-screen pictures of the mesh in any pose, coloured by its weights;
- :class:`SkinningWidget`: the picture, where dragging a bone's tip turns the
  bone and dragging a root joint moves the character (mouse events through
  ``ipyevents``), the sliders (one rotation per bone, the root translation)
  and a label with the measured frame rates; it also exports a pose sequence
  as an animated GIF.

Pictures are rendered by pyvista through EGL where OpenGL works and by
matplotlib otherwise, with the same check and warning as
:mod:`starter.plotting`. The widget always renders: ``DEFORMLAB_NO_PLOTS``
only switches off ``starter.plotting``'s static pictures.
"""

from __future__ import annotations

import time
from collections import deque
from pathlib import Path

import igl
import ipyevents
import ipywidgets as widgets
import numpy as np

from starter import plotting
from starter.offscreen import OffscreenRenderer, picture_size
from starter.posing import bone_joints, bone_transforms
from starter.video import write_mp4
from starter.validation import as_faces, as_float_array, as_handles, as_points

__all__ = ["skinning_weights", "SkinRenderer", "SkinningWidget"]

# matplotlib's tab10: one colour per handle, blended by the weights.
_PALETTE = np.array([
    (31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
    (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207),
], dtype=np.float64)
_BONE = (20, 20, 20)


def skinning_weights(V, F, handle_sets):
    """Bounded biharmonic weights, one column per handle, every row summing to one.

    Computed with ``igl.bbw`` (the kit's student modules cannot use anyone's
    stage 04 solution). ``igl.bbw`` returns *unnormalized* weights, bounded by
    ``[0, 1]`` only up to its solver's tolerance; they are clipped to ``[0, 1]``
    and every row is divided by its sum, as stage 04's ``bbw`` does. A few
    seconds for the ~10k-vertex ``character_fine``: compute them once per kernel.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3} (a planar mesh or a surface).
    F : (f, 3) array_like of int
        Triangles.
    handle_sets : sequence of (k_j,) array_like of int
        The vertices of every handle (one vertex for a point handle, a chain
        for a bone, a set for a region); pairwise disjoint.

    Returns
    -------
    W : (n, m) numpy.ndarray of float64
        ``m = len(handle_sets)``; ``W[i, j]`` is 1 on handle ``j``'s vertices,
        within ``[0, 1]``, and every row sums to one.

    Raises
    ------
    ValueError
        If a shape does not match, an index is out of range or a vertex
        belongs to two handles.
    """
    V = as_points(V, "V")
    F = as_faces(F, len(V))
    if isinstance(handle_sets, (str, bytes)) or not hasattr(handle_sets, "__len__") or len(handle_sets) == 0:
        raise ValueError("handle_sets must be a non-empty sequence of vertex index arrays, one per handle")
    sizes = [np.size(h) for h in handle_sets]
    if min(sizes) == 0:
        raise ValueError(f"handle_sets[{sizes.index(0)}] is empty: every handle needs at least one vertex")
    b = as_handles(np.concatenate([np.ravel(h) for h in handle_sets]), len(V), "handle_sets (concatenated)")
    bc = np.eye(len(handle_sets))[np.repeat(np.arange(len(handle_sets)), sizes)]
    W = np.clip(igl.bbw(V, F, b, bc), 0.0, 1.0)
    return W / W.sum(axis=1, keepdims=True)


class SkinRenderer(OffscreenRenderer):
    """Off-screen pictures of one planar mesh in changing poses, coloured by its skinning weights.

    Every vertex gets the blend ``Σ_j W[i, j] c_j`` of one colour per handle
    (matplotlib's tab10); the bones are drawn as dark segments from their
    first to their last vertex. The view is fixed (centred on the rest pose),
    so consecutive frames line up.

    Parameters
    ----------
    V : (n, 2) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
    W : (n, m) array_like of float
        Skinning weights.
    bones : sequence of (k_j,) array_like of int, optional
        Bone vertex chains to draw as segments.
    size : (int, int)
        Picture width and height in pixels.
    reach : float, optional
        Half the height of the view, centred on the rest bounding box;
        default 1.3 times the largest distance of a rest vertex from that centre.

    Attributes
    ----------
    backend : str
        ``"pyvista"`` (EGL) or ``"matplotlib"``; it becomes ``"matplotlib"``
        for good if a pyvista render fails.
    """

    def __init__(self, V, F, W, bones=None, size=(480, 480), reach=None):
        self.V = as_points(V, "V", dims=(2,))
        self.F = as_faces(F, len(self.V))
        W = as_float_array(W, "W", ndim=2)
        if len(W) != len(self.V):
            raise ValueError(f"W must have one row per vertex ({len(self.V)}), got shape {W.shape}")
        self.size = picture_size(size)
        self.colours = np.clip(W @ _PALETTE[np.arange(W.shape[1]) % len(_PALETTE)], 0, 255).astype(np.uint8)
        self.ends = np.zeros((0, 2), dtype=np.int64)
        if bones is not None:
            bone_joints(self.V, bones)  # checks that every bone is a non-empty integer chain
            self.ends = np.array([[b[0], b[-1]] for b in map(np.asarray, bones)], dtype=np.int64)
            out = (self.ends < 0) | (self.ends >= len(self.V))
            if out.any():
                j = int(np.argwhere(out)[0, 0])
                raise ValueError(f"bones[{j}] ends at vertex {self.ends[j, 1]}, out of range: there are {len(self.V)} vertices")
        lo, hi = self.V.min(axis=0), self.V.max(axis=0)
        self.centre = (lo + hi) / 2
        if reach is None:
            reach = 1.3 * np.linalg.norm(self.V - self.centre, axis=1).max()
        self.reach = float(as_float_array(reach, "reach", ndim=0))
        if self.reach <= 0:
            raise ValueError(f"reach must be positive, got {self.reach}")
        self._start_backend()

    def to_pixels(self, P):
        """Where points appear in the picture.

        Parameters
        ----------
        P : (k, 2) array_like of float
            Points in mesh units.

        Returns
        -------
        (k, 2) numpy.ndarray of float
            Pixel coordinates ``(x, y)``, from the picture's top-left corner,
            ``y`` downwards (as mouse events report them).
        """
        P = as_float_array(P, "P", ndim=2)
        if P.shape[1] != 2:
            raise ValueError(f"P must have shape (k, 2), got {P.shape}")
        pixels_per_unit = self.size[1] / (2 * self.reach)
        half = np.array(self.size, dtype=np.float64) / 2
        return half + (P - self.centre) * pixels_per_unit * np.array([1.0, -1.0])

    def to_world(self, pixels):
        """The mesh-unit points shown at pixels; the inverse of :meth:`to_pixels`.

        Parameters
        ----------
        pixels : (k, 2) array_like of float
            Pixel coordinates ``(x, y)``, from the top-left corner, ``y`` downwards.

        Returns
        -------
        (k, 2) numpy.ndarray of float
        """
        pixels = as_float_array(pixels, "pixels", ndim=2)
        if pixels.shape[1] != 2:
            raise ValueError(f"pixels must have shape (k, 2), got {pixels.shape}")
        units_per_pixel = 2 * self.reach / self.size[1]
        half = np.array(self.size, dtype=np.float64) / 2
        return self.centre + (pixels - half) * units_per_pixel * np.array([1.0, -1.0])

    def png(self, U) -> bytes:
        """:meth:`render` encoded as PNG (fast, lightly compressed).

        Parameters
        ----------
        U : (n, 2) array_like of float

        Returns
        -------
        bytes
        """
        return self.encoded(U, "png", compress_level=1)

    def _render_pyvista(self, U):
        import pyvista as pv

        z = np.zeros((len(U), 1))
        if self._scene is None:
            theme = pv.themes.DocumentTheme()
            theme.multi_samples = 4
            theme.anti_aliasing = None
            theme.background = "white"
            pl = pv.Plotter(off_screen=True, window_size=self.size, theme=theme)
            mesh = pv.PolyData.from_regular_faces(np.hstack([U, z]), self.F)
            mesh.point_data["colour"] = self.colours
            pl.add_mesh(mesh, scalars="colour", rgb=True, lighting=False, show_scalar_bar=False)
            skeleton = None
            if len(self.ends):
                cells = np.column_stack([np.full(len(self.ends), 2), np.arange(2 * len(self.ends)).reshape(-1, 2)])
                # Slightly in front of the mesh so that the bones are never hidden by it.
                skeleton = pv.PolyData(np.hstack([U[self.ends.ravel()], np.full((2 * len(self.ends), 1), 0.01)]),
                                       lines=cells.ravel())
                pl.add_mesh(skeleton, color=np.array(_BONE) / 255, line_width=4, lighting=False)
            pl.enable_parallel_projection()
            cx, cy = self.centre
            pl.camera.focal_point = (cx, cy, 0.0)
            pl.camera.position = (cx, cy, 10.0)
            pl.camera.up = (0.0, 1.0, 0.0)
            pl.camera.parallel_scale = self.reach
            pl.camera.clipping_range = (1.0, 20.0)
            self._scene = (pl, mesh, skeleton)
        pl, mesh, skeleton = self._scene
        mesh.points = np.hstack([U, z])
        if skeleton is not None:
            skeleton.points = np.hstack([U[self.ends.ravel()], np.full((2 * len(self.ends), 1), 0.01)])
        pl.render()
        return np.ascontiguousarray(pl.screenshot(return_img=True)[..., :3])

    def _render_matplotlib(self, U):
        if self._scene is None:
            from matplotlib.collections import LineCollection, PolyCollection
            from matplotlib.figure import Figure

            w, h = self.size
            fig = Figure(figsize=(w / 100, h / 100), dpi=100)
            ax = fig.add_axes((0, 0, 1, 1))
            # Antialiased triangle edges would let the background show through the seams.
            faces = PolyCollection(U[self.F], facecolors=self.colours[self.F].mean(axis=1) / 255, edgecolors="none",
                                   antialiased=False)
            ax.add_collection(faces)
            lines = LineCollection(U[self.ends], colors=[np.array(_BONE) / 255], linewidths=3)
            ax.add_collection(lines)
            half_w = self.reach * w / h
            ax.set_xlim(self.centre[0] - half_w, self.centre[0] + half_w)
            ax.set_ylim(self.centre[1] - self.reach, self.centre[1] + self.reach)
            ax.set_axis_off()
            self._scene = (fig, faces, lines)
        fig, faces, lines = self._scene
        faces.set_verts(U[self.F])
        lines.set_segments(U[self.ends])
        return plotting._figure_image(fig)


class SkinningWidget(widgets.VBox):
    """A skeleton posed with the mouse or sliders, and the linear blend skinning result, re-rendered on every change.

    One slider per bone turns it about its joint (whole degrees, relative to
    its parent, as in :func:`starter.posing.bone_transforms`); two sliders
    translate the roots (whole hundredths of a mesh unit: centimetres for the
    course character, whose unit is the metre). In the picture, pressing the
    mouse near a bone's tip and dragging turns that bone so that it points at
    the mouse; pressing near a root bone's joint and dragging moves the whole
    character with the mouse (:meth:`press`, :meth:`drag`, :meth:`release`;
    the drag moves the sliders, so both stay in step). Every change computes the transforms ``T`` and the
    deformed positions ``U = M @ Tstack`` with ``M = igl.lbs_matrix(V, W)``
    computed once, renders ``U`` into :attr:`image` and updates :attr:`label`
    with the frame rates measured over the last ``history`` changes: LBS
    updates per second (forward kinematics plus the product) and rendered
    frames per second (the whole change: LBS, picture and PNG).

    Parameters
    ----------
    V : (n, 2) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
    W : (n, m) array_like of float
        Skinning weights, one column per bone (e.g. :func:`skinning_weights`).
    bones : sequence of m (k_j,) array_like of int
        Bone vertex chains ordered from the joint (their first vertex).
    parents : (m,) array_like of int
        The bone each bone hangs on, ``-1`` for a root
        (e.g. :data:`starter.posing.CHARACTER_PARENTS`).
    names : sequence of m str, optional
        Slider labels; default ``bone 0``, ``bone 1``, ...
    size : (int, int)
        Picture width and height in pixels.
    max_translation : float
        The translation sliders' range is ``±max_translation`` mesh units
        (at least 0.01).
    history : int
        Number of recent changes the frame rates average over.

    Attributes
    ----------
    M : (n, 3m) numpy.ndarray
        The LBS matrix.
    angle_sliders, translation_sliders : list of ipywidgets.IntSlider
        Integer sliders: a browser snaps a slider's value to its step and sends
        the snapped value back whenever it differs from the kernel's, and such
        late echoes would undo poses set from code (:meth:`set_pose`); whole
        numbers snap to themselves.
    image : ipywidgets.Image
        The current picture (PNG).
    mouse : ipyevents.Event
        The picture's mouse events, throttled to one move per 15 ms.
    pick_radius : float
        How close to a handle, in pixels, a press must be to grab it.
    label : ipywidgets.Label
        The measured frame rates.
    renderer : SkinRenderer
    T : (m, 2, 3) numpy.ndarray
        The current transforms.
    U : (n, 2) numpy.ndarray
        The current deformed positions.
    """

    def __init__(self, V, F, W, bones, parents, names=None, size=(480, 480), max_translation=0.5, history=30):
        V = as_points(V, "V", dims=(2,))
        self.joints = bone_joints(V, bones)
        m = len(self.joints)
        W = as_float_array(W, "W", ndim=2)
        if W.shape != (len(V), m):
            raise ValueError(f"W must have shape ({len(V)}, {m}): one row per vertex, one column per bone; got {W.shape}")
        self.V, self.W = V, W
        self.parents = np.asarray(parents)
        bone_transforms(self.joints, np.zeros(m), self.parents)  # checks parents
        names = [f"bone {j}" for j in range(m)] if names is None else [str(n) for n in names]
        if len(names) != m:
            raise ValueError(f"names must have one entry per bone ({m}), got {len(names)}")
        max_translation = float(as_float_array(max_translation, "max_translation", ndim=0))
        if max_translation < 0.01:
            raise ValueError(f"max_translation must be at least 0.01 (one slider step), got {max_translation}")
        if not isinstance(history, (int, np.integer)) or history < 1:
            raise ValueError(f"history must be a positive integer, got {history!r}")
        self.M = igl.lbs_matrix(V, W)
        self.renderer = SkinRenderer(V, F, W, bones, size)
        style = {"description_width": "8em"}
        layout = widgets.Layout(width="30em")
        self.angle_sliders = [
            widgets.IntSlider(value=0, min=-180, max=180, description=f"{n} (°)", style=style, layout=layout)
            for n in names
        ]
        reach = int(round(100 * max_translation))
        self.translation_sliders = [
            widgets.IntSlider(value=0, min=-reach, max=reach, description=f"move {axis} (cm)", style=style, layout=layout)
            for axis in "xy"
        ]
        width, height = self.renderer.size
        self.image = widgets.Image(format="png", width=width, height=height)
        self.mouse = ipyevents.Event(
            source=self.image,
            watched_events=["mousedown", "mousemove", "mouseup", "mouseleave"],
            prevent_default_action=True,
            throttle_or_debounce="throttle",
            wait=15,
        )
        self.mouse.on_dom_event(self._mouse_event)
        self.pick_radius = 20.0
        self._grabbed = None
        self.label = widgets.Label()
        self._timings = deque(maxlen=int(history))
        self._paused = False
        self.roots = np.flatnonzero(self.parents < 0)
        self.tips = V[self.renderer.ends[:, 1]]
        super().__init__([widgets.HBox([self.image, widgets.VBox(self.angle_sliders + self.translation_sliders)]),
                          self.label])
        for slider in self.angle_sliders + self.translation_sliders:
            slider.observe(self._changed, names="value")
        self.update()

    @property
    def angles(self) -> np.ndarray:
        """(m,) the sliders' bone angles in radians."""
        return np.radians([s.value for s in self.angle_sliders])

    @property
    def translation(self) -> np.ndarray:
        """(2,) the sliders' root translation in mesh units."""
        return np.array([s.value for s in self.translation_sliders]) / 100

    def _changed(self, change):
        if not self._paused:
            self.update()

    def _positions(self, angles, translation):
        T = bone_transforms(self.joints, angles, self.parents, translation)
        return T, self.M @ T.transpose(0, 2, 1).reshape(-1, 2)

    def update(self):
        """Recompute ``T`` and ``U`` from the sliders, render them and refresh the label."""
        started = time.perf_counter()
        self.T, self.U = self._positions(self.angles, self.translation)
        skinned = time.perf_counter()
        self.image.value = self.renderer.png(self.U)
        self._timings.append((skinned - started, time.perf_counter() - started))
        rates = self.frame_rates()
        self.label.value = (
            f"LBS: {rates['lbs_updates_per_second']:,.0f} updates/s · rendered: "
            f"{rates['rendered_frames_per_second']:.1f} frames/s ({self.renderer.backend}, "
            f"{len(self.V):,} vertices, mean of the last {len(self._timings)} changes)"
        )

    def handle_pixels(self) -> dict:
        """Where the draggable handles are in the current picture.

        Returns
        -------
        dict
            ``tips``: (m, 2) pixel coordinates of every bone's tip; ``roots``:
            (r, 2) those of the root bones' joints, in the order of
            :attr:`roots`.
        """
        return {
            "tips": self.renderer.to_pixels(self._apply(self.T, np.arange(len(self.tips)), self.tips)),
            "roots": self.renderer.to_pixels(self._apply(self.T, self.roots, self.joints[self.roots])),
        }

    @staticmethod
    def _apply(T, which, points):
        return np.einsum("kij,kj->ki", T[which, :, :2], points) + T[which, :, 2]

    def press(self, x, y):
        """Grab the tip nearest to a pixel within :attr:`pick_radius`, else the nearest root joint within it.

        Parameters
        ----------
        x, y : float
            Pixel coordinates in the picture (from its top-left corner).

        Returns
        -------
        tuple or None
            ``("tip", j)`` (dragging turns bone ``j``), ``("root", j)``
            (dragging moves the character) or ``None`` if nothing is close.
        """
        at = np.array([[float(x), float(y)]])
        pixels = self.handle_pixels()
        # Tips before roots: a bone folded back puts its tip on a root joint, and the
        # tip under the mouse is the one the user means (a root is grabbed where no tip is).
        for kind, ids, points in (("tip", range(len(pixels["tips"])), pixels["tips"]), ("root", self.roots, pixels["roots"])):
            if len(points) == 0:
                continue
            distances = np.linalg.norm(points - at[0], axis=1)
            nearest = int(np.argmin(distances))
            if distances[nearest] <= self.pick_radius:
                j = int(ids[nearest])
                self._grabbed = (kind, j, self.renderer.to_world(at)[0], self.translation)
                return kind, j
        self._grabbed = None
        return None

    def drag(self, x, y):
        """Move the grabbed handle to a pixel (nothing happens if none is grabbed).

        A tip turns its bone about the bone's current joint until it points
        at the mouse; a root joint moves the character by the mouse's
        displacement since the press. Sliders snap to whole degrees and
        centimetres and stop at their ranges.

        Parameters
        ----------
        x, y : float
            Pixel coordinates in the picture.
        """
        if self._grabbed is None:
            return
        kind, j, start, translation = self._grabbed
        at = self.renderer.to_world([[float(x), float(y)]])[0]
        if kind == "tip":
            joint = self._apply(self.T, [j], self.joints[[j]])[0]
            tip = self._apply(self.T, [j], self.tips[[j]])[0]
            now, wanted = tip - joint, at - joint
            turn = np.degrees(np.arctan2(now[0] * wanted[1] - now[1] * wanted[0], now @ wanted))
            slider = self.angle_sliders[j]
            self._move_sliders([slider], [(slider.value + turn + 180) % 360 - 180])
        else:
            self._move_sliders(self.translation_sliders, 100 * (translation + at - start))

    def release(self, x=None, y=None):
        """Let go of the grabbed handle, after moving it to a pixel if one is given.

        The browser throttles mouse moves and sends the button's release at
        once, so the last move can arrive after the release, or never: the
        release's own position is where the drag ends.

        Parameters
        ----------
        x, y : float, optional
            Pixel coordinates of the release; without them the handle stays
            where the last move put it.
        """
        if x is not None and y is not None:
            self.drag(x, y)
        self._grabbed = None

    def _event_pixels(self, event):
        """Picture pixel coordinates of a browser mouse event.

        ipyevents' ``dataX``/``dataY`` scale by the image's natural size,
        which reads 0 while the browser decodes a new frame, so an event
        during a redraw claims (0, 0). The position within the element's
        box, scaled by the box's size, does not depend on the frame.
        """
        width, height = self.renderer.size
        box_w, box_h = event.get("boundingRectWidth") or 0, event.get("boundingRectHeight") or 0
        if box_w > 0 and box_h > 0 and "relativeX" in event:
            return event["relativeX"] * width / box_w, event["relativeY"] * height / box_h
        return event.get("dataX"), event.get("dataY")

    def _mouse_event(self, event):
        kind = event.get("type")
        x, y = self._event_pixels(event)
        if kind in ("mouseup", "mouseleave"):
            self.release(x, y)
        elif x is None or y is None:
            return
        elif kind == "mousedown":
            self.press(x, y)
        elif kind == "mousemove" and self._grabbed is not None:
            self.drag(x, y)

    def set_pose(self, angles, translation=None):
        """Move the sliders to a pose, then update once.

        The sliders hold whole degrees and hundredths: the pose is rounded to
        them (and clamped to their ranges); :attr:`angles` and
        :attr:`translation` give the pose shown.

        Parameters
        ----------
        angles : (m,) array_like of float
            Bone angles in radians.
        translation : (2,) array_like of float, optional
            Root translation in mesh units; default zero.
        """
        angles = as_float_array(angles, "angles", ndim=1)
        if len(angles) != len(self.angle_sliders):
            raise ValueError(f"angles must have one entry per bone ({len(self.angle_sliders)}), got {len(angles)}")
        translation = np.zeros(2) if translation is None else as_float_array(translation, "translation", ndim=1)
        if translation.shape != (2,):
            raise ValueError(f"translation must have shape (2,), got {translation.shape}")
        self._move_sliders(self.angle_sliders + self.translation_sliders,
                           np.concatenate([np.degrees(angles), 100 * translation]))

    def _move_sliders(self, sliders, values):
        """Set sliders to values rounded to whole steps and clamped to their ranges, then update once."""
        self._paused = True
        try:
            for slider, value in zip(sliders, values):
                slider.value = int(np.clip(np.rint(value), slider.min, slider.max))
        finally:
            self._paused = False
        self.update()

    def frame_rates(self) -> dict:
        """The frame rates measured over the last ``history`` changes.

        Returns
        -------
        dict
            ``lbs_updates_per_second`` (forward kinematics and ``M @ Tstack``)
            and ``rendered_frames_per_second`` (the whole change, picture and
            PNG included), both floats.
        """
        lbs, total = np.mean(np.array(self._timings), axis=0)
        return {"lbs_updates_per_second": 1.0 / max(lbs, 1e-9), "rendered_frames_per_second": 1.0 / max(total, 1e-9)}

    def export_animation(self, path, angles, translations=None, fps=20):
        """Write a pose sequence as an animated GIF (looping) or an MP4 video, rendered like the widget.

        The sliders are not moved. A GIF needs only Pillow, which merges
        consecutive identical frames into one (adding their durations). An
        MP4 (H.264, the format slides and learning platforms play) needs
        PyAV, whose wheel carries its own FFmpeg: ``pip install av`` or the
        ``deformlab[video]`` extra.

        Parameters
        ----------
        path : str or os.PathLike
            Target file; its name must end in ``.gif`` or ``.mp4``.
        angles : (k, m) array_like of float
            Bone angles in radians, one row per frame.
        translations : (k, 2) array_like of float, optional
            Root translation per frame; default zero.
        fps : float
            Frames per second (a GIF stores whole milliseconds per frame).

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        path = Path(path)
        kind = path.suffix.lower()
        if kind not in (".gif", ".mp4"):
            raise ValueError(f"path must end in .gif or .mp4, got {str(path)!r}")
        angles = as_float_array(angles, "angles", ndim=2)
        k, m = angles.shape
        if m != len(self.angle_sliders) or k == 0:
            raise ValueError(f"angles must have shape (k, {len(self.angle_sliders)}) with k >= 1, got {angles.shape}")
        translations = np.zeros((k, 2)) if translations is None else as_float_array(translations, "translations", ndim=2)
        if translations.shape != (k, 2):
            raise ValueError(f"translations must have shape ({k}, 2), one row per frame, got {translations.shape}")
        fps = float(as_float_array(fps, "fps", ndim=0))
        if fps <= 0:
            raise ValueError(f"fps must be positive, got {fps}")
        frames = (self.renderer.render(self._positions(a, t)[1]) for a, t in zip(angles, translations))
        if kind == ".mp4":
            write_mp4(path, frames, fps)
            return path
        from PIL import Image

        images = [Image.fromarray(frame) for frame in frames]
        images[0].save(path, save_all=True, append_images=images[1:], duration=max(1, round(1000 / fps)), loop=0)
        return path
