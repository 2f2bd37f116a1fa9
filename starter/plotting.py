"""Static pictures for the notebooks: meshes, deformations, weights, point sets, energies.

Every ``show_*`` function renders a PNG-ready picture and returns it as a
:class:`Picture`, an ``(h, w, 3)`` uint8 RGB numpy array. Inside IPython or
Jupyter it also displays the picture as a PNG at once, so the picture is
stored in the notebook and survives ``nbconvert --to html``; the returned
array does not display a second time when it ends a cell.

Backends:

- 2D meshes, point sets and energy curves are drawn with matplotlib (Agg,
  no pyplot, so nothing else pops up).
- 3D meshes are rendered off screen by pyvista through EGL (no X server).
  Where no OpenGL is available (checked once per process in a subprocess,
  so a crashing driver cannot take the kernel down) they are drawn with
  matplotlib instead, after a one-line warning.

Environment variables:

- ``DEFORMLAB_NO_PLOTS=1``: every function returns ``None`` at once without
  rendering (the grader sets it; any value but ``""`` and ``"0"`` counts).
- ``DEFORMLAB_PLOT_BACKEND``: ``auto`` (default), ``pyvista`` (skip the
  OpenGL check) or ``matplotlib`` (never use pyvista).

Importing this module imports neither pyvista nor matplotlib; the functions
import them when they first draw.
"""

from __future__ import annotations

import io
import os
import subprocess
import sys
import warnings
from dataclasses import dataclass, field

import numpy as np

from starter.validation import as_faces, as_float_array, as_points, as_vertices

# VTK chooses its window class when it is first imported; EGL renders off
# screen without an X server.
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

__all__ = [
    "Picture",
    "show_mesh",
    "show_deformation",
    "show_meshes",
    "show_weights",
    "show_points",
    "show_energy",
    "opengl_available",
]

PANEL_PIXELS = 400
"""Width and height of one picture panel, in pixels."""
MAX_COLUMNS = 4
"""Panels per row; more panels wrap onto further rows."""

_EDGE_LIMIT = 6000  # above this many triangles edges would hide the colours
_FILL = "#a6c8e6"
_EDGE = (0.15, 0.15, 0.15, 0.35)
_HANDLE = "#e31a1c"
_UNDER, _OVER = "#ff00ff", "#ff0000"
# Solvers leave round-off like -1e-17 in weights that are bounded in exact
# arithmetic; only departures beyond this get the out-of-range colours.
_RANGE_TOL = 1e-6

_opengl: bool | None = None
_opengl_reason = ""
_warned = False
_plotter = None

_PROBE = """
import os
os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
import pyvista as pv
pl = pv.Plotter(off_screen=True, window_size=(64, 64))
pl.add_mesh(pv.Sphere(), color="red")
img = pl.screenshot(return_img=True)
pl.close()
print("rendered", img.shape, bool(img.std() > 0))
"""


class Picture(np.ndarray):
    """An ``(h, w, 3)`` uint8 RGB image that IPython shows as a PNG.

    A plain numpy array in every other respect. A picture the ``show_*``
    function already displayed in the current cell is not displayed again
    when it is the cell's value.
    """

    _shown_in = None

    def _repr_png_(self):
        return _png(np.asarray(self))

    def _ipython_display_(self):
        from IPython.display import Image, display

        if self.ndim != 3 or self.dtype != np.uint8:
            display(np.asarray(self))
            return
        shell = _ipython()
        if shell is not None and self._shown_in == shell.execution_count:
            return
        display(Image(data=_png(np.asarray(self)), format="png"))


def _png(img: np.ndarray) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(img).save(buffer, format="png")
    return buffer.getvalue()


def _ipython():
    module = sys.modules.get("IPython")
    return module.get_ipython() if module is not None else None


def _no_plots() -> bool:
    return os.environ.get("DEFORMLAB_NO_PLOTS", "") not in ("", "0")


def _finish(img: np.ndarray) -> Picture:
    """Wrap, display inside IPython, return."""
    picture = np.ascontiguousarray(img[..., :3], dtype=np.uint8).view(Picture)
    shell = _ipython()
    if shell is not None:
        from IPython.display import Image, display

        display(Image(data=_png(np.asarray(picture)), format="png"))
        picture._shown_in = shell.execution_count
    return picture


# ---------------------------------------------------------------- backends


def opengl_available() -> bool:
    """Whether pyvista can render off screen here (checked once, then cached).

    The check renders a small sphere in a subprocess, so a missing or broken
    OpenGL driver cannot crash the calling process.

    Returns
    -------
    bool
    """
    global _opengl, _opengl_reason
    if _opengl is None:
        try:
            run = subprocess.run(
                [sys.executable, "-c", _PROBE], capture_output=True, text=True, timeout=180
            )
            _opengl = run.returncode == 0 and "rendered (64, 64, 3) True" in run.stdout
            tail = (run.stderr.strip().splitlines() or [f"exit code {run.returncode}"])[-1]
            _opengl_reason = "" if _opengl else tail
        except (OSError, subprocess.SubprocessError) as exc:
            _opengl, _opengl_reason = False, str(exc)
    return _opengl


def _backend_setting() -> str:
    value = os.environ.get("DEFORMLAB_PLOT_BACKEND", "auto").strip().lower() or "auto"
    if value not in ("auto", "pyvista", "matplotlib"):
        raise ValueError(f"DEFORMLAB_PLOT_BACKEND must be auto, pyvista or matplotlib, got {value!r}")
    return value


def _warn_fallback(reason: str, stacklevel: int) -> None:
    """Warn once per process; ``stacklevel`` points at the caller of ``show_*``."""
    global _warned
    if not _warned:
        _warned = True
        warnings.warn(
            f"starter.plotting: 3D pictures use matplotlib, pyvista cannot render here ({reason})",
            RuntimeWarning,
            stacklevel=stacklevel,
        )


def _use_pyvista() -> bool:
    setting = _backend_setting()
    if setting == "matplotlib":
        return False
    if setting == "pyvista" or opengl_available():
        return True
    _warn_fallback(_opengl_reason or "no OpenGL", stacklevel=5)
    return False


# ---------------------------------------------------------------- inputs


@dataclass
class _Panel:
    V: np.ndarray
    F: np.ndarray
    title: str | None = None
    scalars: np.ndarray | None = None
    cmap: str = "viridis"
    clim: tuple[float, float] | None = None
    out_of_range: bool = False
    colorbar: bool = False
    marks: list = field(default_factory=list)  # (indices, colour, size)
    label: str | None = None  # what the colour bar measures
    categories: tuple[str, ...] | None = None  # integer codes 0..k-1 named on the colour bar
    view: np.ndarray | None = None  # 3D: direction from the centre to the camera


def _mesh(V, F, name_V="V", name_F="F"):
    V = as_vertices(V, name_V)
    return V, as_faces(F, len(V), name_F)


def _handle_groups(handles, n: int, name: str = "handles") -> list[np.ndarray]:
    """``None``, one index array, or a list of index arrays (one per handle)."""
    if handles is None:
        return []
    if isinstance(handles, (list, tuple)) and any(np.ndim(h) >= 1 for h in handles):
        raw = [(f"{name}[{k}]", h) for k, h in enumerate(handles)]
    else:
        raw = [(name, handles)]
    groups = []
    for label, h in raw:
        a = np.asarray(h)
        if a.ndim != 1 or (a.size and (a.dtype == bool or not np.issubdtype(a.dtype, np.integer))):
            raise ValueError(f"{label} must be a 1-D integer array of vertex indices, got shape {a.shape} and dtype {a.dtype}")
        a = a.astype(np.int64)
        if a.size and (a.min() < 0 or a.max() >= n):
            raise ValueError(f"{label} has a vertex index out of range [0, {n}): {int(a[(a < 0) | (a >= n)][0])}")
        groups.append(a)
    return groups


def _scalars(s, n: int, f: int, name: str = "scalars"):
    if s is None:
        return None
    a = as_float_array(s, name, ndim=1)
    if len(a) not in (n, f):
        raise ValueError(f"{name} must have one value per vertex ({n}) or per triangle ({f}), got {len(a)}")
    return a


def _as_3d(V: np.ndarray) -> np.ndarray:
    return V if V.shape[1] == 3 else np.column_stack([V, np.zeros(len(V))])


# ---------------------------------------------------------------- drawing


def _render(panels: list[_Panel], link_views: bool = True) -> np.ndarray:
    """Draw the panels on a grid of at most ``MAX_COLUMNS`` columns."""
    if all(p.V.shape[1] == 2 for p in panels):
        return _mpl_render(panels, link_views, three_d=False)
    for p in panels:
        p.V = _as_3d(p.V)
    if _use_pyvista():
        try:
            return _pv_render(panels, link_views)
        except Exception as exc:  # a driver that passed the check can still fail
            global _opengl, _opengl_reason, _plotter
            _opengl, _opengl_reason, _plotter = False, f"{type(exc).__name__}: {exc}", None
            _warn_fallback(_opengl_reason, stacklevel=4)
    return _mpl_render(panels, link_views, three_d=True)


def _bounds(panels: list[_Panel], link_views: bool) -> list[np.ndarray]:
    """Per panel ``(2, d)`` [min; max] box: shared by all panels when linked."""
    boxes = [np.stack([p.V.min(axis=0), p.V.max(axis=0)]) for p in panels]
    if link_views:
        shared = np.stack([np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)])
        boxes = [shared] * len(panels)
    return boxes


def _clim(p: _Panel):
    if p.categories is not None:
        return (-0.5, len(p.categories) - 0.5)
    if p.clim is not None:
        return p.clim
    lo, hi = float(p.scalars.min()), float(p.scalars.max())
    # an end within round-off of 0 (a volume change of -7.65e-20) is printed as 0
    scale = max(abs(lo), abs(hi))
    lo, hi = (0.0 if abs(v) <= 1e-9 * scale else v for v in (lo, hi))
    return (lo, hi) if hi > lo else (lo - 0.5, hi + 0.5)


def _colormap(p: _Panel):
    import matplotlib

    cmap = matplotlib.colormaps[p.cmap]
    if p.categories is not None:
        return cmap.resampled(len(p.categories))  # one flat colour per category, no blend between them
    return cmap.with_extremes(under=_UNDER, over=_OVER) if p.out_of_range else cmap


def _pv_render(panels: list[_Panel], link_views: bool) -> np.ndarray:
    """Render each panel with one reused off-screen plotter and tile the images.

    Reusing the plotter keeps the compiled shaders: a new window costs a
    shader compilation, which dominates with software OpenGL.
    """
    global _plotter
    import pyvista as pv

    if _plotter is None:
        theme = pv.themes.DocumentTheme()
        theme.multi_samples = 4
        theme.anti_aliasing = None
        _plotter = pv.Plotter(off_screen=True, window_size=(PANEL_PIXELS, PANEL_PIXELS), theme=theme)
    pl = _plotter
    images = []
    for p, box in zip(panels, _bounds(panels, link_views)):
        pl.clear()
        mesh = pv.PolyData.from_regular_faces(p.V, p.F)
        kwargs = dict(show_edges=len(p.F) <= _EDGE_LIMIT, edge_color=_EDGE[:3], line_width=0.5)
        if p.scalars is None:
            pl.add_mesh(mesh, color=_FILL, **kwargs)
        else:
            bar = dict(title=p.label or " ", color="black", vertical=False, n_labels=3, fmt="%.3g")
            if p.out_of_range:
                bar.update(below_label="<0", above_label=">1")
            if p.categories is not None:  # pyvista's bar has no tick names: the title lists the codes
                bar.update(n_labels=0, title=(f"{p.label}: " if p.label else "")
                           + ", ".join(f"{k} {name}" for k, name in enumerate(p.categories)))
            pl.add_mesh(
                mesh,
                scalars=p.scalars,
                cmap=_colormap(p) if p.categories is not None else p.cmap,
                n_colors=len(p.categories) if p.categories is not None else 256,
                clim=_clim(p),
                below_color=_UNDER if p.out_of_range else None,
                above_color=_OVER if p.out_of_range else None,
                show_scalar_bar=p.colorbar,
                scalar_bar_args=bar,
                **kwargs,
            )
        for idx, colour, size in p.marks:
            if len(idx):
                pl.add_points(p.V[idx], color=colour, point_size=size, render_points_as_spheres=True)
        if p.title:
            pl.add_text(p.title, position="upper_edge", font_size=10, color="black")
        centre = box.mean(axis=0)
        direction = np.array([1.0, 1.0, 1.0]) if p.view is None else p.view
        pl.camera.focal_point = centre
        pl.camera.position = centre + direction
        pl.camera.up = _up(direction)
        pl.reset_camera(bounds=box.T.ravel())
        images.append(pl.screenshot(return_img=True)[..., :3])
    pl.clear()
    return _tile(images)


def _tile(images: list[np.ndarray]) -> np.ndarray:
    cols = min(len(images), MAX_COLUMNS)
    rows = -(-len(images) // cols)
    h, w = images[0].shape[:2]
    out = np.full((rows * h, cols * w, 3), 255, dtype=np.uint8)
    for k, img in enumerate(images):
        r, c = divmod(k, cols)
        out[r * h:(r + 1) * h, c * w:(c + 1) * w] = img
    return out


def _figure(n_panels: int, projection: str | None = None):
    from matplotlib.figure import Figure

    cols = min(n_panels, MAX_COLUMNS)
    rows = -(-n_panels // cols)
    fig = Figure(figsize=(cols * PANEL_PIXELS / 100, rows * PANEL_PIXELS / 100), dpi=100, layout="constrained")
    kw = {} if projection is None else {"projection": projection}
    axes = [fig.add_subplot(rows, cols, k + 1, **kw) for k in range(n_panels)]
    return fig, axes


def _figure_image(fig) -> np.ndarray:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba())[..., :3].copy()


def _up(direction: np.ndarray) -> tuple[float, float, float]:
    """z up, unless the camera looks along z: then y up."""
    d = np.asarray(direction, dtype=float)
    return (0.0, 1.0, 0.0) if abs(d[2]) > 0.99 * np.linalg.norm(d) else (0.0, 0.0, 1.0)


def _mpl_render(panels: list[_Panel], link_views: bool, three_d: bool) -> np.ndarray:
    fig, axes = _figure(len(panels), "3d" if three_d else None)
    for ax, p, box in zip(axes, panels, _bounds(panels, link_views)):
        mappable = (_mpl_panel_3d if three_d else _mpl_panel_2d)(ax, p, box)
        if mappable is not None and p.colorbar:
            extend = "both" if p.out_of_range else "neither"
            if p.categories is not None:
                bar = fig.colorbar(mappable, ax=ax, shrink=0.6, ticks=range(len(p.categories)))
                bar.ax.set_yticklabels(p.categories)
            else:
                bar = fig.colorbar(mappable, ax=ax, shrink=0.6, extend=extend)
            if p.label:
                bar.set_label(p.label)
        if p.title:
            ax.set_title(p.title, fontsize=10)
    return _figure_image(fig)


def _norm(p: _Panel):
    from matplotlib.colors import Normalize

    return Normalize(*_clim(p))


def _mpl_panel_2d(ax, p: _Panel, box: np.ndarray):
    from matplotlib.collections import PolyCollection

    x, y = p.V[:, 0], p.V[:, 1]
    edges = len(p.F) <= _EDGE_LIMIT
    mappable = None
    if p.scalars is None:
        ax.add_collection(PolyCollection(p.V[p.F], facecolor=_FILL, edgecolor=_EDGE if edges else "none", linewidth=0.3))
    else:
        cmap, norm = _colormap(p), _norm(p)
        if len(p.scalars) == len(p.V):
            mappable = ax.tripcolor(x, y, p.F, p.scalars, shading="gouraud", cmap=cmap, norm=norm)
        else:
            mappable = ax.tripcolor(x, y, p.F, facecolors=p.scalars, cmap=cmap, norm=norm)
        if edges:
            ax.triplot(x, y, p.F, color=_EDGE, linewidth=0.3)
    for idx, colour, size in p.marks:
        ax.scatter(x[idx], y[idx], s=size**2 / 2, c=colour, edgecolors="black", linewidths=0.5, zorder=3)
    pad = 0.03 * max(float(np.ptp(box, axis=0).max()), 1e-12)
    ax.set_xlim(box[0, 0] - pad, box[1, 0] + pad)
    ax.set_ylim(box[0, 1] - pad, box[1, 1] + pad)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return mappable


def _mpl_panel_3d(ax, p: _Panel, box: np.ndarray):
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import to_rgba
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    tri = p.V[p.F]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    light = np.array([1.0, 0.5, 1.5]) / np.linalg.norm([1.0, 0.5, 1.5])
    shade = 0.45 + 0.55 * np.abs(normal @ light)
    mappable = None
    if p.scalars is None:
        colours = np.tile(to_rgba(_FILL), (len(p.F), 1))
    else:
        cmap, norm = _colormap(p), _norm(p)
        values = p.scalars[p.F].mean(axis=1) if len(p.scalars) == len(p.V) else p.scalars
        colours = cmap(norm(values))
        mappable = ScalarMappable(norm=norm, cmap=cmap)
    colours[:, :3] *= shade[:, None]
    edges = _EDGE if len(p.F) <= _EDGE_LIMIT else "none"
    ax.add_collection3d(Poly3DCollection(tri, facecolors=colours, edgecolors=edges, linewidths=0.2))
    for idx, colour, size in p.marks:
        ax.scatter(*p.V[idx].T, s=size**2 / 2, c=colour, edgecolors="black", linewidths=0.5, depthshade=False)
    ax.set_xlim(box[0, 0], box[1, 0])
    ax.set_ylim(box[0, 1], box[1, 1])
    ax.set_zlim(box[0, 2], box[1, 2])
    ax.set_box_aspect(np.maximum(np.ptp(box, axis=0), 1e-3 * np.ptp(box, axis=0).max()))
    d = np.array([1.0, 1.0, 1.0]) if p.view is None else np.asarray(p.view, dtype=float)
    # the same view as pyvista's: elevation and azimuth of the camera direction
    ax.view_init(elev=np.degrees(np.arcsin(d[2] / np.linalg.norm(d))), azim=np.degrees(np.arctan2(d[1], d[0])))
    ax.set_axis_off()
    return mappable


def _marks(groups: list[np.ndarray], size: float = 9.0) -> list:
    if not groups:
        return []
    return [(np.unique(np.concatenate(groups)), _HANDLE, size)]


# ---------------------------------------------------------------- public


def show_mesh(V, F, scalars=None, handles=None, title=None, cmap="viridis", label=None):
    """Picture of one mesh, optionally colour-mapped, with handle vertices marked.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles.
    scalars : (n,) or (f,) array_like of float, optional
        Per-vertex (smoothly shaded) or per-triangle values, with a colour bar.
    handles : (h,) array_like of int or list of them, optional
        Vertices to mark (red dots).
    title : str, optional
    cmap : str
        A matplotlib colormap name.
    label : str, optional
        What the colours measure, written on the colour bar.

    Returns
    -------
    Picture or None
        ``(400, 400, 3)`` uint8 image; ``None`` when ``DEFORMLAB_NO_PLOTS``
        is set.
    """
    if _no_plots():
        return None
    V, F = _mesh(V, F)
    panel = _Panel(V, F, title=title, scalars=_scalars(scalars, len(V), len(F)), cmap=cmap,
                   marks=_marks(_handle_groups(handles, len(V))), label=label)
    panel.colorbar = panel.scalars is not None
    return _finish(_render([panel]))


def show_deformation(V, U, F, handles=None, titles=("rest", "deformed")):
    """Rest and deformed mesh side by side, on the same scale, handles marked.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    U : (n, d) array_like of float
        Deformed positions.
    F : (f, 3) array_like of int
    handles : (h,) array_like of int or list of them, optional
        Constrained vertices, marked in both panels.
    titles : pair of str

    Returns
    -------
    Picture or None
        ``(400, 800, 3)`` uint8 image; ``None`` when ``DEFORMLAB_NO_PLOTS`` is set.
    """
    if _no_plots():
        return None
    V, F = _mesh(V, F)
    U = as_float_array(U, "U", ndim=2)
    if U.shape != V.shape:
        raise ValueError(f"U must have the shape of V {V.shape}, got {U.shape}")
    if len(titles) != 2:
        raise ValueError(f"titles must be two strings (rest, deformed), got {len(titles)}")
    marks = _marks(_handle_groups(handles, len(V)))
    return _finish(_render([_Panel(V, F, title=titles[0], marks=marks), _Panel(U, F, title=titles[1], marks=marks)]))


def show_meshes(meshes, titles=None, link_views=True, label=None, clim=None, cmap="viridis", categories=None,
                view=None):
    """Several meshes side by side (e.g. poses), at most four per row.

    Parameters
    ----------
    meshes : sequence of (V, F) or (V, F, scalars)
        ``scalars`` per vertex or per triangle, as in :func:`show_mesh`.
    titles : sequence of str, optional
        One per mesh.
    link_views : bool
        Draw every mesh in the same box and view, so sizes compare.
    label : str or sequence of str, optional
        What the colours measure, written on the colour bar: one for all
        meshes or one per mesh.
    clim : (2,) sequence of float, optional
        One colour range for every mesh with scalars, so colours compare
        across panels (default: each panel its own minimum and maximum).
    cmap : str
        A matplotlib colormap name.
    categories : sequence of str, optional
        The scalars are integer codes ``0 .. k-1`` of these ``k`` categories
        (e.g. ``("kept", "flipped")``): drawn in ``k`` flat colours, named on
        the colour bar.
    view : (3,) array_like of float, optional
        3D only: the direction from the meshes' centre to the camera (default
        ``(1, 1, 1)``, an isometric view); ``(0, 0, 1)`` looks down the z axis.

    Returns
    -------
    Picture or None
        ``(400 * rows, 400 * columns, 3)`` uint8 image; ``None`` when
        ``DEFORMLAB_NO_PLOTS`` is set.
    """
    if _no_plots():
        return None
    if isinstance(meshes, (str, bytes)) or not hasattr(meshes, "__len__") or len(meshes) == 0:
        raise ValueError("meshes must be a non-empty sequence of (V, F) or (V, F, scalars) tuples")
    if titles is not None and len(titles) != len(meshes):
        raise ValueError(f"titles must have one entry per mesh ({len(meshes)}), got {len(titles)}")
    labels = [label] * len(meshes) if label is None or isinstance(label, str) else list(label)
    if len(labels) != len(meshes):
        raise ValueError(f"label must be one string or one per mesh ({len(meshes)}), got {len(labels)}")
    if clim is not None:
        clim = tuple(float(c) for c in np.asarray(clim, dtype=float).ravel())
        if len(clim) != 2 or not clim[0] < clim[1]:
            raise ValueError(f"clim must be two increasing numbers (low, high), got {clim}")
    if categories is not None:
        categories = tuple(str(c) for c in categories)
        if len(categories) < 2:
            raise ValueError(f"categories must name at least two categories, got {categories}")
    if view is not None:
        view = as_float_array(view, "view", ndim=1)
        if view.shape != (3,) or not np.linalg.norm(view) > 0:
            raise ValueError(f"view must be a non-zero 3-vector (the direction to the camera), got {view.tolist()}")
    panels = []
    for k, item in enumerate(meshes):
        if not isinstance(item, (tuple, list)) or len(item) not in (2, 3):
            raise ValueError(f"meshes[{k}] must be a tuple (V, F) or (V, F, scalars)")
        V, F = _mesh(item[0], item[1], f"meshes[{k}][0]", f"meshes[{k}][1]")
        s = _scalars(item[2], len(V), len(F), f"meshes[{k}][2]") if len(item) == 3 else None
        if s is not None and categories is not None and not np.isin(s, np.arange(len(categories))).all():
            raise ValueError(f"meshes[{k}][2] must hold category codes 0..{len(categories) - 1}")
        panels.append(_Panel(V, F, title=None if titles is None else titles[k], scalars=s, colorbar=s is not None,
                             cmap=cmap, clim=clim, label=labels[k], categories=categories, view=view))
    return _finish(_render(panels, link_views))


def show_weights(V, F, W, handles=None, columns=None, cmap="viridis", titles=None, label="weight"):
    """One panel per weight column, colour-mapped on [0, 1].

    Values below 0 are magenta and above 1 red (beyond a 1e-6 round-off
    margin), so a violated bound is visible; each panel's title names it
    (``titles``) and gives its column's minimum and maximum.

    Parameters
    ----------
    V : (n, d) array_like of float
    F : (f, 3) array_like of int
    W : (n, m) or (n,) array_like of float
        Weights, one column per handle.
    handles : (h,) array_like of int or list of them, optional
        Handle vertices, marked white in every panel. With a list of ``m``
        arrays (one per column, as for ``handle_constraints``), panel ``j``
        marks handle ``j`` black instead.
    columns : sequence of int, optional
        The columns to show (default: all).
    cmap : str
        A matplotlib colormap name.
    titles : sequence of str, optional
        One name per shown column, e.g. ``"BBW: left foot"`` (the method and
        the handle); default ``"column j"``.
    label : str
        What the colour bar measures.

    Returns
    -------
    Picture or None
        ``(400 * rows, 400 * columns, 3)`` uint8 image, at most four panels per
        row; ``None`` when ``DEFORMLAB_NO_PLOTS`` is set.
    """
    if _no_plots():
        return None
    V, F = _mesh(V, F)
    W = as_float_array(W, "W")
    if W.ndim == 1:
        W = W[:, None]
    if W.ndim != 2 or len(W) != len(V):
        raise ValueError(f"W must have shape ({len(V)}, m), one row per vertex, got {W.shape}")
    m = W.shape[1]
    cols = list(range(m)) if columns is None else [int(c) for c in np.asarray(columns).ravel()]
    if not cols or min(cols) < 0 or max(cols) >= m:
        raise ValueError(f"columns must be non-empty column indices of W in [0, {m}), got {cols}")
    if titles is not None and (isinstance(titles, str) or len(titles) != len(cols)):
        raise ValueError(f"titles must have one entry per shown column ({len(cols)}), got {titles!r}")
    groups = _handle_groups(handles, len(V))
    per_column = len(groups) == m and m > 1
    panels = []
    for k, j in enumerate(cols):
        w = W[:, j]
        if per_column:
            others = [g for k, g in enumerate(groups) if k != j]
            # Its own handle sits where w = 1 (bright), the others where w = 0 (dark).
            marks = [(np.concatenate(others) if others else np.zeros(0, np.int64), "white", 7.0), (groups[j], "black", 9.0)]
        else:
            marks = [(g, "white", 7.0) for g in groups]
        # Round-off just outside [0, 1] is drawn (and printed) as 0 or 1, not as out of range.
        clipped = np.clip(w, 0.0, 1.0)
        shown = np.where(np.abs(w - clipped) <= _RANGE_TOL, clipped, w)
        name = f"column {j}" if titles is None else titles[k]
        title = f"{name}: min {shown.min() + 0.0:.3g}, max {shown.max():.3g}"
        panels.append(_Panel(V, F, title=title, scalars=shown, cmap=cmap, clim=(0.0, 1.0), out_of_range=True,
                             colorbar=True, marks=marks, label=label))
    return _finish(_render(panels))


def show_points(P, Q, P_aligned=None, title=None):
    """2D or 3D point sets before (and after) alignment, correspondences as thin lines.

    Parameters
    ----------
    P : (k, d) array_like of float
        Source points (blue), ``d`` in {2, 3}.
    Q : (k, d) array_like of float
        Target points (orange); ``P[i]`` corresponds to ``Q[i]``.
    P_aligned : (k, d) array_like of float, optional
        The source after alignment (green), shown in a second panel.
    title : str, optional

    Returns
    -------
    Picture or None
        ``(400, 400, 3)``, or ``(400, 800, 3)`` with ``P_aligned``, uint8
        image; ``None`` when ``DEFORMLAB_NO_PLOTS`` is set.
    """
    if _no_plots():
        return None
    P = as_points(P, "P")
    Q = as_points(Q, "Q")
    if Q.shape != P.shape:
        raise ValueError(f"Q must have the shape of P {P.shape} (one target per source point), got {Q.shape}")
    pairs = [(P, "P", "#1f77b4")]
    if P_aligned is not None:
        A = as_points(P_aligned, "P_aligned")
        if A.shape != P.shape:
            raise ValueError(f"P_aligned must have the shape of P {P.shape}, got {A.shape}")
        pairs.append((A, "aligned P", "#2ca02c"))
    d = P.shape[1]
    fig, axes = _figure(len(pairs), "3d" if d == 3 else None)
    everything = np.concatenate([Q] + [S for S, _, _ in pairs])
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    pad = 0.05 * max(float((hi - lo).max()), 1e-12)
    for ax, (S, label, colour) in zip(axes, pairs):
        segments = np.stack([S, Q], axis=1)
        if d == 2:
            from matplotlib.collections import LineCollection

            ax.add_collection(LineCollection(segments, colors="0.6", linewidths=0.6, zorder=1))
            ax.scatter(*Q.T, s=14, c="#ff7f0e", marker="x", label="Q", zorder=2)
            ax.scatter(*S.T, s=12, c=colour, label=label, zorder=3)
            ax.set_xlim(lo[0] - pad, hi[0] + pad)
            ax.set_ylim(lo[1] - pad, hi[1] + pad)
            ax.set_aspect("equal")
        else:
            from mpl_toolkits.mplot3d.art3d import Line3DCollection

            ax.add_collection3d(Line3DCollection(segments, colors="0.6", linewidths=0.6))
            ax.scatter(*Q.T, s=14, c="#ff7f0e", marker="x", label="Q", depthshade=False)
            ax.scatter(*S.T, s=12, c=colour, label=label, depthshade=False)
            for set_lim, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
                set_lim(lo[k] - pad, hi[k] + pad)
            ax.set_box_aspect(np.maximum(hi - lo, 1e-3 * float((hi - lo).max())) + 2 * pad)
        ax.legend(loc="best", fontsize=8)
        ax.set_title("after alignment" if S is not P else "before", fontsize=10)
    if title:
        fig.suptitle(title, fontsize=11)
    return _finish(_figure_image(fig))


def show_energy(energies, title=None, log=True):
    """Energy per iteration, one line per run.

    Parameters
    ----------
    energies : sequence of float, or dict of str to sequence of float
        ``energies[k]`` is the energy after iteration ``k + 1``; a dict draws
        one labelled line per entry.
    title : str, optional
    log : bool
        Logarithmic energy axis (used only when every value is positive).

    Returns
    -------
    Picture or None
        ``(400, 400, 3)`` uint8 image; ``None`` when ``DEFORMLAB_NO_PLOTS`` is set.
    """
    if _no_plots():
        return None
    runs = dict(energies) if isinstance(energies, dict) else {None: energies}
    if not runs:
        raise ValueError("energies must not be empty")
    curves = {}
    for label, values in runs.items():
        name = "energies" if label is None else f"energies[{label!r}]"
        a = as_float_array(values, name, ndim=1)
        if len(a) == 0:
            raise ValueError(f"{name} is empty: give at least one energy")
        curves[label] = a
    fig, (ax,) = _figure(1)
    for label, a in curves.items():
        ax.plot(np.arange(1, len(a) + 1), a, marker="o" if len(a) <= 30 else None, markersize=3, label=label)
    if log and all((a > 0).all() for a in curves.values()):
        ax.set_yscale("log")
    ax.set_xlabel("iteration")
    ax.set_ylabel("energy")
    ax.grid(True, which="both", alpha=0.3)
    if len(curves) > 1 or None not in curves:
        ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return _finish(_figure_image(fig))
