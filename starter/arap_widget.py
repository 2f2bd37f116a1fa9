"""Interactive as-rigid-as-possible deformation in a notebook: libigl's tutorial 405 with the mouse.

A 3D surface mesh with handle regions is deformed by ARAP (spokes and rims,
libigl's ``igl.arap_solve``, as stage 03 computes it) while a handle is
dragged. Every frame starts from the previous frame's positions (the
lecture's "use the previous frame as the initial guess"), runs as many
local-global iterations as the frame rate allows, computes the ARAP energy of
the result and renders it off screen into an image.

- :class:`ArapRenderer`: off-screen pictures of the surface from a fixed
  orthographic view, the handles coloured, and the mapping between pixels and
  the view plane;
- :class:`ArapWidget`: the picture, where pressing on a handle and dragging
  moves it in the view plane (mouse events through ``ipyevents``), and a label
  with the energy, the iterations per frame and the measured frame rates; it
  also exports a scripted handle motion as a GIF or an MP4.

The widget computes its frames on a thread of its own: mouse events only move
the handles' targets, and each frame takes the latest target, so the picture
follows the mouse at the frame rate however fast events arrive. When the
handles stop, frames go on (each one more iterations from the last) until the
energy stops decreasing: the shape settles into the ARAP minimum.

Pictures are rendered by pyvista through EGL where OpenGL works and by
matplotlib otherwise, with the same check and warning as
:mod:`starter.plotting`.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from pathlib import Path

import igl
import ipyevents
import ipywidgets as widgets
import numpy as np
import scipy.sparse as sp

from starter import plotting
from starter.offscreen import OffscreenRenderer, picture_size
from starter.video import write_mp4
from starter.validation import as_faces, as_float_array, as_handles, as_points, component_without

__all__ = ["ArapRenderer", "ArapWidget"]

# matplotlib's tab10 colours for the handles (red, blue, green first); the rest of the surface is light grey.
_PALETTE = np.array([
    (214, 39, 40), (31, 119, 180), (44, 160, 44), (255, 127, 14), (148, 103, 189),
    (140, 86, 75), (227, 119, 194), (188, 189, 34), (23, 190, 207), (127, 127, 127),
], dtype=np.uint8)
_SURFACE = (205, 205, 200)


def _handle_sets(handle_sets, n):
    """Checked handle sets: a list of int64 arrays, non-empty and pairwise disjoint."""
    if isinstance(handle_sets, (str, bytes)) or not hasattr(handle_sets, "__len__") or len(handle_sets) == 0:
        raise ValueError("handle_sets must be a non-empty sequence of vertex index arrays, one per handle")
    sets = [np.asarray(h).ravel() for h in handle_sets]
    sizes = [len(h) for h in sets]
    if min(sizes) == 0:
        raise ValueError(f"handle_sets[{sizes.index(0)}] is empty: every handle needs at least one vertex")
    b = as_handles(np.concatenate(sets), n, "handle_sets (concatenated)")
    return np.split(b, np.cumsum(sizes)[:-1])


def _largest_rotation_traces(cells):
    """``max over rotations R of tr(R S)`` for every ``S`` of an ``(n, 3, 3)`` stack (see ``ArapWidget.arap_energy``)."""
    # entry-major (3, 3, n): every pass below runs over contiguous rows, half the time of (n, 3) slices
    entries = cells.reshape(-1, 9).T.copy()
    size = np.sqrt(np.einsum("in,in->n", entries, entries))
    entries /= np.where(size > 0, size, 1.0)
    rows = entries.reshape(3, 3, -1)
    # cofactor row a = row a+1 x row a+2 (indices mod 3)
    cofactors = np.empty_like(rows)
    for a in range(3):
        u, v = rows[(a + 1) % 3], rows[(a + 2) % 3]
        for b in range(3):
            np.subtract(u[(b + 1) % 3] * v[(b + 2) % 3], u[(b + 2) % 3] * v[(b + 1) % 3], out=cofactors[a, b])
    det = np.einsum("an,an->n", rows[0], cofactors[0])
    cof2 = np.einsum("abn,abn->n", cofactors, cofactors)
    lam = np.full(len(size), np.sqrt(3.0))
    for _ in range(60):
        square = lam * lam - 1.0
        slope = 4.0 * lam * square - 8.0 * det
        step = (square * square - 8.0 * det * lam - 4.0 * cof2) / np.where(slope > 0, slope, np.inf)
        lam -= step
        if np.all(np.abs(step) <= 1e-15 * lam):
            break
    return lam * size


class ArapRenderer(OffscreenRenderer):
    """Off-screen pictures of one surface in changing shapes, seen from a fixed orthographic view.

    The surface is light grey and lit, every handle's vertices have a colour
    of their own (matplotlib's tab10). The view never moves, so consecutive
    frames line up and pixels map to the view plane by :meth:`to_pixels` and
    :meth:`to_offset`.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
    handle_sets : sequence of (k_j,) array_like of int
        The vertices of every handle, pairwise disjoint.
    size : (int, int)
        Picture width and height in pixels.
    view : (3,) array_like of float
        The direction the camera looks in (from the camera to the mesh).
    up : (3,) array_like of float
        The direction shown upwards; not parallel to ``view``.
    reach : float, optional
        Half the height of the view in mesh units, centred on the rest
        bounding box; default 1.5 times what the rest shape needs, so that
        dragged handles stay in the picture.

    Attributes
    ----------
    backend : str
        ``"pyvista"`` (EGL) or ``"matplotlib"``; it becomes ``"matplotlib"``
        for good if a pyvista render fails.
    right, upward : (3,) numpy.ndarray
        Unit vectors of the view plane shown to the right and upwards.
    """

    def __init__(self, V, F, handle_sets, size=(560, 360), view=(-0.45, 1.0, -0.5), up=(0.0, 0.0, 1.0), reach=None):
        self.V = as_points(V, "V", dims=(3,))
        self.F = as_faces(F, len(self.V))
        sets = _handle_sets(handle_sets, len(self.V))
        self.size = size = picture_size(size)
        view, up = as_float_array(view, "view", ndim=1), as_float_array(up, "up", ndim=1)
        if view.shape != (3,) or up.shape != (3,):
            raise ValueError(f"view and up must be 3-vectors, got shapes {view.shape} and {up.shape}")
        right = np.cross(view, up)
        if np.linalg.norm(view) == 0 or np.linalg.norm(right) <= 1e-9 * np.linalg.norm(view) * np.linalg.norm(up):
            raise ValueError(f"view {view} and up {up} must be non-zero and not parallel")
        self.view = view / np.linalg.norm(view)
        self.right = right / np.linalg.norm(right)
        self.upward = np.cross(self.right, self.view)
        self.centre = (self.V.min(axis=0) + self.V.max(axis=0)) / 2
        if reach is None:
            seen = (self.V - self.centre) @ np.column_stack([self.right, self.upward])
            reach = 1.5 * max(np.abs(seen[:, 1]).max(), np.abs(seen[:, 0]).max() * size[1] / size[0])
        self.reach = float(as_float_array(reach, "reach", ndim=0))
        if self.reach <= 0:
            raise ValueError(f"reach must be positive, got {self.reach}")
        self.colours = np.tile(np.array(_SURFACE, dtype=np.uint8), (len(self.V), 1))
        for j, h in enumerate(sets):
            self.colours[h] = _PALETTE[j % len(_PALETTE)]
        self._start_backend()

    @property
    def pixels_per_unit(self) -> float:
        return self.size[1] / (2 * self.reach)

    def to_pixels(self, P):
        """Where points appear in the picture.

        Parameters
        ----------
        P : (k, 3) array_like of float
            Points in mesh units.

        Returns
        -------
        (k, 2) numpy.ndarray of float
            Pixel coordinates ``(x, y)`` from the picture's top-left corner,
            ``y`` downwards (as mouse events report them).
        """
        P = as_float_array(P, "P", ndim=2)
        if P.shape[1] != 3:
            raise ValueError(f"P must have shape (k, 3), got {P.shape}")
        seen = (P - self.centre) @ np.column_stack([self.right, -self.upward])
        return np.array(self.size, dtype=np.float64) / 2 + seen * self.pixels_per_unit

    def to_offset(self, shift):
        """The displacement in the view plane that moves a point's picture by ``shift`` pixels.

        Parameters
        ----------
        shift : (2,) array_like of float
            Pixels ``(dx, dy)``, ``dy`` downwards.

        Returns
        -------
        (3,) numpy.ndarray
            In mesh units, perpendicular to the viewing direction.
        """
        shift = as_float_array(shift, "shift", ndim=1)
        if shift.shape != (2,):
            raise ValueError(f"shift must have shape (2,), got {shift.shape}")
        return (shift[0] * self.right - shift[1] * self.upward) / self.pixels_per_unit

    def jpeg(self, U, quality=90) -> bytes:
        """:meth:`render` encoded as JPEG (a fifth of PNG's encoding time here, and smaller)."""
        return self.encoded(U, "jpeg", quality=int(quality))

    def _render_pyvista(self, U):
        import pyvista as pv

        if self._scene is None:
            theme = pv.themes.DocumentTheme()
            # No multisampling: on a software OpenGL (llvmpipe) it costs more than the solve.
            theme.multi_samples = 0
            theme.anti_aliasing = None
            theme.background = "white"
            # one light above the camera and some ambient: the default five-light kit took ~9 ms a
            # picture on software OpenGL (llvmpipe) against ~6 ms, a third of a frame at 30 per second
            pl = pv.Plotter(off_screen=True, window_size=self.size, theme=theme, lighting="none")
            pl.add_light(pv.Light(position=(0.2, 0.5, 1.0), light_type="camera light"))
            mesh = pv.PolyData.from_regular_faces(U.copy(), self.F)
            mesh.point_data["colour"] = self.colours
            pl.add_mesh(mesh, scalars="colour", rgb=True, show_scalar_bar=False, ambient=0.25, diffuse=0.8)
            pl.enable_parallel_projection()
            distance = 20.0 * self.reach
            pl.camera.focal_point = tuple(self.centre)
            pl.camera.position = tuple(self.centre - distance * self.view)
            pl.camera.up = tuple(self.upward)
            pl.camera.parallel_scale = self.reach
            pl.camera.clipping_range = (0.5 * distance, 1.5 * distance)
            self._scene = (pl, mesh)
        pl, mesh = self._scene
        mesh.points = U
        pl.render()
        return np.ascontiguousarray(pl.screenshot(return_img=True)[..., :3])

    def _render_matplotlib(self, U):
        """Flat-shaded triangles in the view plane, painted back to front."""
        if self._scene is None:
            from matplotlib.collections import PolyCollection
            from matplotlib.figure import Figure

            w, h = self.size
            fig = Figure(figsize=(w / 100, h / 100), dpi=100)
            ax = fig.add_axes((0, 0, 1, 1))
            faces = PolyCollection(np.zeros((0, 3, 2)), edgecolors="none", antialiased=False)
            ax.add_collection(faces)
            ax.set_xlim(0, w)
            ax.set_ylim(h, 0)
            ax.set_axis_off()
            self._scene = (fig, faces)
        fig, faces = self._scene
        corners = U[self.F]
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
        light = 0.35 + 0.65 * np.abs(normals @ self.view)
        order = np.argsort(-(corners.mean(axis=1) @ self.view))  # farthest first
        colour = self.colours[self.F].mean(axis=1) / 255 * light[:, None]
        faces.set_verts(self.to_pixels(corners.reshape(-1, 3)).reshape(-1, 3, 2)[order])
        faces.set_facecolor(np.clip(colour[order], 0, 1))
        return plotting._figure_image(fig)


class ArapWidget(widgets.VBox):
    """A surface whose handles are dragged with the mouse, deformed as rigidly as possible, redrawn frame by frame.

    Pressing the mouse on a handle's vertices (within :attr:`pick_radius`
    pixels) and dragging moves that handle rigidly in the view plane; the
    other handles stay where they are. Frames are computed on the widget's
    own thread: each frame solves ARAP with ``igl.arap_solve`` (spokes and
    rims) from the previous frame's positions for the latest handle targets,
    running as many local-global iterations as fit the frame budget
    (``1 / target_fps`` less the time the energy and the picture take,
    measured over the last frames; at least one, at most ``max_iterations``),
    then computes the ARAP energy of the result, renders it into
    :attr:`image` and updates :attr:`label`. While the handles stay put,
    frames go on, and once they have not moved for ``settle_after`` seconds
    (the drag has ended, not just paused between two mouse events) each frame
    runs twice the iterations of the one before (up to ``max_iterations``:
    nobody waits for the next frame), until the energy decreases by
    less than ``settle_tol`` of itself in a frame or ``settle_iterations``
    have run since the handles stopped: every local-global iteration lowers
    the energy, so the shape settles towards the ARAP minimum for the handles
    where they are (ARAP converges slowly on large bends; the cap keeps an
    idle widget from computing for long after the eye sees no change).

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions of a surface mesh.
    F : (f, 3) array_like of int
        Triangles.
    handle_sets : sequence of (k_j,) array_like of int
        The vertices of every handle (pairwise disjoint); together at least
        one vertex in every connected component.
    names : sequence of str, optional
        Handle names, shown in the label while one is dragged; default
        ``handle 0``, ``handle 1``, ...
    size : (int, int)
        Picture width and height in pixels.
    target_fps : float
        The frame rate the iteration count per frame aims at.
    max_iterations : int
        Most local-global iterations in one frame.
    settle_tol : float
        Frames at still handles stop once the energy falls by less than this
        fraction in a frame (or by less than its rounding, ``1e-12`` of the
        rest shape's ``3 Σ C ‖e‖²``).
    settle_iterations : int
        Most iterations at still handles before frames stop.
    settle_after : float
        Seconds without a handle move after which frames settle with growing
        iteration counts.
    history : int
        Number of recent frames the rates and the budget average over.
    live : bool
        Compute frames on the widget's thread as the handles move (the
        notebook's case). Without it, nothing runs until :meth:`step` or
        :meth:`settle` is called (scripts and tests).
    **view
        ``view``, ``up``, ``reach`` for :class:`ArapRenderer`.

    Attributes
    ----------
    U : (n, 3) numpy.ndarray
        The current positions.
    energy : float
        Their ARAP energy (spokes and rims, each vertex's rotation the best
        one for ``U``).
    offsets : (m, 3) numpy.ndarray
        How far every handle has been moved from its rest position.
    image : ipywidgets.Image
        The current picture (JPEG).
    label : ipywidgets.Label
        Frame number, energy, iterations per frame and frame rates.
    frames : collections.deque of dict
        The last ``history`` frames: ``frame`` (a counter), ``moved`` (the
        handle targets differ from the previous frame's), ``iterations``,
        ``energy``, ``solve_s``, ``total_s`` (solve, energy, picture and JPEG,
        wall clock) and ``cpu_s`` (the process's CPU time over the frame,
        every thread: the renderer's included).
    mouse : ipyevents.Event
        The picture's mouse events, throttled to one move per 15 ms.
    pick_radius : float
        How close to a handle's vertex, in pixels, a press must be to grab it.
    renderer : ArapRenderer
    """

    def __init__(self, V, F, handle_sets, names=None, size=(560, 360), target_fps=30.0, max_iterations=20,
                 settle_tol=1e-4, settle_iterations=300, settle_after=0.3, history=30, live=True,
                 **view):
        V = as_points(V, "V", dims=(3,))
        F = as_faces(F, len(V))
        self.handle_sets = _handle_sets(handle_sets, len(V))
        m = len(self.handle_sets)
        names = [f"handle {j}" for j in range(m)] if names is None else [str(n) for n in names]
        if len(names) != m:
            raise ValueError(f"names must have one entry per handle ({m}), got {len(names)}")
        self.names = names
        self.target_fps = float(as_float_array(target_fps, "target_fps", ndim=0))
        if self.target_fps <= 0:
            raise ValueError(f"target_fps must be positive, got {self.target_fps}")
        if not isinstance(max_iterations, (int, np.integer)) or max_iterations < 1:
            raise ValueError(f"max_iterations must be a positive integer, got {max_iterations!r}")
        self.max_iterations = int(max_iterations)
        self.settle_tol = float(as_float_array(settle_tol, "settle_tol", ndim=0))
        if not self.settle_tol >= 0:
            raise ValueError(f"settle_tol must be non-negative, got {self.settle_tol}")
        if not isinstance(settle_iterations, (int, np.integer)) or settle_iterations < 1:
            raise ValueError(f"settle_iterations must be a positive integer, got {settle_iterations!r}")
        self.settle_iterations = int(settle_iterations)
        self.settle_after = float(as_float_array(settle_after, "settle_after", ndim=0))
        if not self.settle_after >= 0:
            raise ValueError(f"settle_after must be non-negative, got {self.settle_after}")
        if not isinstance(history, (int, np.integer)) or history < 1:
            raise ValueError(f"history must be a positive integer, got {history!r}")
        self.V, self.F = V, F
        self._b = np.concatenate(self.handle_sets)
        self._arap = igl.ARAPData()
        self._arap.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
        vertex = component_without(F, len(V), self._b)
        if vertex is not None:
            raise ValueError(f"handle_sets must include a vertex of every connected component of the mesh: the "
                             f"component of vertex {vertex} has none, so its position is undetermined")
        igl.arap_precomputation(V, F, 3, self._b.astype(np.int32), self._arap)
        self._energy_terms(V, F)
        self.renderer = ArapRenderer(V, F, self.handle_sets, size, **view)
        self.offsets = np.zeros((m, 3))
        self.U = V.copy()
        self.energy = 0.0
        self.frames = deque(maxlen=int(history))
        self._count = 0
        self._still = 0  # settling frames so far
        self._still_iterations = 0  # iterations since the handles last moved
        self._moved_at = -np.inf
        self._shown_offsets = self.offsets.copy()
        self._settled = True
        self._version = self._drawn = 0
        self._compute = threading.Lock()  # one frame at a time, whoever computes it
        self._wake = threading.Condition()
        self._closing = False
        self._grabbed = None
        self.pick_radius = 20.0
        width, height = self.renderer.size
        self.image = widgets.Image(format="jpeg", width=width, height=height)
        self.mouse = ipyevents.Event(
            source=self.image,
            watched_events=["mousedown", "mousemove", "mouseup", "mouseleave"],
            prevent_default_action=True,
            throttle_or_debounce="throttle",
            wait=15,
        )
        self.mouse.on_dom_event(self._mouse_event)
        self.label = widgets.Label()
        super().__init__([self.image, self.label])
        self._draw(0, 0.0, 0.0, moved=False)
        self._thread = None
        if live:
            self._thread = threading.Thread(target=self._run, name="ArapWidget", daemon=True)
            self._thread.start()

    # ------------------------------------------------------------ energy

    def _energy_terms(self, V, F):
        """What the energy reuses: the rest term, ``L`` and the linear map from positions to cell covariances.

        A cell's covariance gets, from each triangle ``t`` at its vertex,
        ``Σ_k w_k e'_kᵀ`` with ``w_k = C[t, k] e_k`` and ``e'_k = u_head(k) - u_tail(k)``:
        ``+w_k`` on the head's row and ``-w_k`` on the tail's, so the covariances
        are one sparse product with ``U``.
        """
        weights = igl.cotmatrix_entries(V, F)  # ½ cot of the angle at each corner, the opposite edge's weight
        tail, head = F[:, [1, 2, 0]], F[:, [2, 0, 1]]  # the edge opposite corner k
        rest = V[head] - V[tail]
        self._rest_term = 3.0 * float(np.sum(weights * (rest * rest).sum(axis=2)))
        self._laplacian = igl.cotmatrix(V, F)  # Σ_t Σ_k C ‖e'‖² = -tr(Uᵀ L U)
        w = weights[:, :, None] * rest  # (f, k, a)
        n, f = len(V), len(F)
        # entry (3 owner + a, vertex): every corner of t owns a cell, every edge k adds ±w to its ends' columns
        owner = np.broadcast_to(F[:, :, None, None, None], (f, 3, 3, 2, 3))
        vertex = np.broadcast_to(np.stack([head, tail], axis=-1)[:, None, :, :, None], (f, 3, 3, 2, 3))
        value = np.broadcast_to(np.stack([w, -w], axis=2)[:, None, :, :, :], (f, 3, 3, 2, 3))
        a = np.broadcast_to(np.arange(3), (f, 3, 3, 2, 3))
        self._covariances = sp.csr_matrix((value.ravel(), ((3 * owner + a).ravel(), vertex.ravel())), shape=(3 * n, n))

    def arap_energy(self, U) -> float:
        """The spokes-and-rims ARAP energy of positions ``U``, every cell with its best rotation.

        ``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²`` with ``C`` from
        ``igl.cotmatrix_entries``: the energy ``igl.arap_solve`` lowers.

        Parameters
        ----------
        U : (n, 3) array_like of float

        Returns
        -------
        float

        Notes
        -----
        Expanding the squares, the energy is ``3 Σ C ‖e'‖² + 3 Σ C ‖e‖² - 2 Σ_i
        max_R tr(R S_i)`` for the cells' covariances ``S_i``, and the largest
        ``tr(R S)`` over rotations is the largest eigenvalue of Horn's 4x4
        quaternion matrix of ``S``, the largest root of
        ``(λ² - ‖S‖²)² - 8 det(S) λ - 4 ‖cof S‖²``: no rotation needs to be
        formed. Its roots are real, so Newton's method from the bound
        ``√3 ‖S‖`` descends onto the largest one.
        """
        U = as_float_array(U, "U", ndim=2)
        if U.shape != self.V.shape:
            raise ValueError(f"U must have the shape of V {self.V.shape}, got {U.shape}")
        cells = (self._covariances @ U).reshape(-1, 3, 3)
        deformed = -3.0 * float(np.einsum("ij,ij->", U, self._laplacian @ U))
        return max(deformed + self._rest_term - 2.0 * float(np.sum(_largest_rotation_traces(cells))), 0.0)

    # ------------------------------------------------------------ frames

    def targets(self, offsets=None) -> np.ndarray:
        """(h, 3) where the handle vertices go for ``offsets`` (default the current ones), in handle order."""
        offsets = self.offsets if offsets is None else offsets
        return self.V[self._b] + np.repeat(offsets, [len(h) for h in self.handle_sets], axis=0)

    def _budget(self) -> int:
        """Iterations that fit in a frame: ``1 / target_fps`` less the rest of a frame, over one iteration's time."""
        if not self.frames:
            return 1
        iteration = np.mean([f["solve_s"] / f["iterations"] for f in self.frames])
        rest = np.mean([f["total_s"] - f["solve_s"] for f in self.frames])
        return int(np.clip((1.0 / self.target_fps - rest) // max(iteration, 1e-9), 1, self.max_iterations))

    def step(self, offsets=None) -> dict:
        """Compute, render and show one frame for handle ``offsets`` (default :attr:`offsets`).

        Returns
        -------
        dict
            The frame's record (see :attr:`frames`).
        """
        with self._compute:
            if offsets is None:
                with self._wake:
                    offsets = self.offsets.copy()
            offsets = np.array(offsets, dtype=np.float64)
            moved = not np.array_equal(offsets, self._shown_offsets)
            iterations = self._budget()
            if not moved and time.monotonic() - self._moved_at >= self.settle_after:
                # the drag has ended and nobody waits for the next frame: double the iterations each frame
                iterations = max(iterations, min(self.max_iterations, 2 ** self._still))
                self._still += 1
            else:
                self._still = 0
            self._still_iterations = 0 if moved else self._still_iterations + iterations
            started, cpu = time.perf_counter(), time.process_time()
            self._arap.max_iter = iterations
            U = igl.arap_solve(self.targets(offsets), self._arap, self.U)
            solved = time.perf_counter()
            energy = self.arap_energy(U)
            previous = self.energy
            self.U, self.energy, self._shown_offsets = U, energy, offsets
            self._count += 1
            self._draw(iterations, solved - started, started, moved, cpu)
            record = self.frames[-1]
            # settled: the energy fell by less than settle_tol of itself, or to rounding (near the rest shape)
            self._settled = not moved and (previous - energy <= self.settle_tol * energy + 1e-12 * self._rest_term
                                           or self._still_iterations >= self.settle_iterations)
            return record

    def _draw(self, iterations, solve_s, started, moved, cpu=0.0):
        self.image.value = self.renderer.jpeg(self.U)
        if iterations:
            self.frames.append({"frame": self._count, "moved": moved, "iterations": iterations, "energy": self.energy,
                                "solve_s": solve_s, "total_s": time.perf_counter() - started,
                                "cpu_s": time.process_time() - cpu})
        rates = self.frame_rates()
        grabbed = self._grabbed  # the mouse's thread may let go meanwhile
        self.label.value = (
            f"frame {self._count} ({'handles moved' if moved else 'handles still'}) · ARAP energy {self.energy:.9g} · "
            f"{rates['iterations_per_frame']:.1f} iterations/frame · {rates['frames_per_second']:.1f} frames/s "
            f"(solve + render; solve alone {rates['solve_frames_per_second']:.0f}/s) · {self.renderer.backend}, "
            f"{len(self.V):,} vertices" + ("" if grabbed is None else f" · dragging the {self.names[grabbed[0]]}")
        )

    def settle(self, max_frames=200) -> int:
        """Compute frames at the current offsets until the energy settles; returns how many ran."""
        for k in range(1, int(max_frames) + 1):
            self.step()
            if self._settled:
                return k
        return int(max_frames)

    def frame_rates(self) -> dict:
        """Rates over the last ``history`` frames.

        Returns
        -------
        dict
            ``frames_per_second`` (whole frames: solve, energy, picture, JPEG),
            ``solve_frames_per_second`` (``igl.arap_solve`` alone),
            ``frames_per_cpu_second`` (whole frames per second of the
            process's CPU time: what a machine with a core to spare gets) and
            ``iterations_per_frame``; zeros before the first frame.
        """
        keys = ("frames_per_second", "solve_frames_per_second", "frames_per_cpu_second", "iterations_per_frame")
        if not self.frames:
            return dict.fromkeys(keys, 0.0)
        mean = {k: float(np.mean([f[k] for f in self.frames])) for k in ("total_s", "solve_s", "cpu_s", "iterations")}
        return dict(zip(keys, (1.0 / max(mean["total_s"], 1e-9), 1.0 / max(mean["solve_s"], 1e-9),
                               1.0 / max(mean["cpu_s"], 1e-9), mean["iterations"])))

    # ------------------------------------------------------------ the frame thread

    def _run(self):
        while True:
            with self._wake:
                while not self._closing and self._drawn == self._version and self._settled:
                    self._wake.wait()
                if self._closing:
                    return
                version = self._version
            try:
                self.step()
            except Exception as exc:  # show it where the student looks, and keep the thread for the next move
                self.label.value = f"frame failed: {type(exc).__name__}: {exc}"
                self._settled = True
            self._drawn = version

    def move_handle(self, j, offset):
        """Move handle ``j`` to ``offset`` (mesh units) from its rest position; frames follow.

        Parameters
        ----------
        j : int
        offset : (3,) array_like of float
        """
        offset = as_float_array(offset, "offset", ndim=1)
        if offset.shape != (3,):
            raise ValueError(f"offset must have shape (3,), got {offset.shape}")
        if not 0 <= int(j) < len(self.handle_sets):
            raise ValueError(f"j must be a handle index in [0, {len(self.handle_sets)}), got {j}")
        with self._wake:
            self.offsets[int(j)] = offset
            self._moved_at = time.monotonic()
            self._version += 1
            self._settled = False
            self._wake.notify()

    def wait_until_settled(self, timeout=60.0) -> bool:
        """Wait until the frame thread has shown the latest handles and the energy settled; ``True`` if it did."""
        deadline = time.monotonic() + float(timeout)
        while time.monotonic() < deadline:
            with self._wake:
                if self._drawn == self._version and self._settled:
                    return True
            time.sleep(0.01)
        return False

    def close(self):
        """Stop the frame thread, release the renderer and close the widgets."""
        if not hasattr(self, "_wake"):  # __init__ failed before the widget was whole
            return super().close()
        with self._wake:
            self._closing = True
            self._wake.notify()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join(timeout=10)
        self.renderer.close()
        self.mouse.close()
        super().close()

    # ------------------------------------------------------------ the mouse

    def handle_pixels(self) -> list:
        """Where every handle's vertices are in the current picture: a list of ``(k_j, 2)`` arrays."""
        return [self.renderer.to_pixels(self.U[h]) for h in self.handle_sets]

    def press(self, x, y):
        """Grab the handle with a vertex nearest to a pixel, if within :attr:`pick_radius`; returns its index or ``None``."""
        at = np.array([float(x), float(y)])
        best, j_best = np.inf, None
        for j, pixels in enumerate(self.handle_pixels()):
            d = float(np.min(np.linalg.norm(pixels - at, axis=1)))
            if d < best:
                best, j_best = d, j
        self._grabbed = (j_best, at, self.offsets[j_best].copy()) if best <= self.pick_radius else None
        return None if self._grabbed is None else j_best

    def drag(self, x, y):
        """Move the grabbed handle with the mouse, in the view plane (nothing happens if none is grabbed)."""
        if self._grabbed is None:
            return
        j, start, offset = self._grabbed
        self.move_handle(j, offset + self.renderer.to_offset(np.array([float(x), float(y)]) - start))

    def release(self, x=None, y=None):
        """Let go of the grabbed handle, after moving it to the release's pixel if one is given."""
        if x is not None and y is not None:
            self.drag(x, y)
        self._grabbed = None

    def _event_pixels(self, event):
        """Picture pixels of a browser mouse event (see ``SkinningWidget._event_pixels``: the element's box, not
        the image's natural size, which reads 0 while a new frame decodes)."""
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

    # ------------------------------------------------------------ export

    def export_animation(self, path, offsets, fps=20, iterations=None):
        """Write a scripted handle motion as an animated GIF (looping) or an MP4 video, rendered like the widget.

        Each frame warm-starts from the one before it, as in the widget; the
        widget's own shape is not changed. A GIF needs only Pillow; an MP4
        (H.264) needs PyAV (``pip install av`` or the ``deformlab[video]`` extra).

        Parameters
        ----------
        path : str or os.PathLike
            Target file; its name must end in ``.gif`` or ``.mp4``.
        offsets : (k, m, 3) array_like of float
            Every handle's offset from rest, one block per frame.
        fps : float
            Frames per second (a GIF stores whole milliseconds per frame).
        iterations : int, optional
            Local-global iterations per frame; default the widget's current
            budget.

        Returns
        -------
        pathlib.Path
            ``path``.
        """
        path = Path(path)
        kind = path.suffix.lower()
        if kind not in (".gif", ".mp4"):
            raise ValueError(f"path must end in .gif or .mp4, got {str(path)!r}")
        offsets = as_float_array(offsets, "offsets", ndim=3)
        m = len(self.handle_sets)
        if offsets.shape[1:] != (m, 3) or len(offsets) == 0:
            raise ValueError(f"offsets must have shape (k, {m}, 3) with k >= 1, got {offsets.shape}")
        fps = float(as_float_array(fps, "fps", ndim=0))
        if fps <= 0:
            raise ValueError(f"fps must be positive, got {fps}")
        if iterations is None:
            iterations = self._budget()
        if not isinstance(iterations, (int, np.integer)) or iterations < 1:
            raise ValueError(f"iterations must be a positive integer, got {iterations!r}")

        def frames():
            U = self.V.copy()
            for block in offsets:
                with self._compute:
                    self._arap.max_iter = int(iterations)
                    U = igl.arap_solve(self.targets(block), self._arap, U)
                yield self.renderer.render(U)

        if kind == ".mp4":
            write_mp4(path, frames(), fps)
            return path
        from PIL import Image

        images = [Image.fromarray(frame) for frame in frames()]
        images[0].save(path, save_all=True, append_images=images[1:], duration=max(1, round(1000 / fps)), loop=0)
        return path
