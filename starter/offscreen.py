"""Off-screen pictures of a mesh in changing shapes, shared by the interactive demos' renderers.

A renderer draws through pyvista (EGL) where it works and through matplotlib
otherwise, and falls back to matplotlib for good if a pyvista render fails.
An OpenGL context works only on the thread that made it current, and a kernel
may deliver widget events on another thread than cell execution: pyvista
always runs on one thread of the renderer's own.
"""

from __future__ import annotations

import io
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from starter import plotting
from starter.validation import as_float_array


def picture_size(size) -> tuple[int, int]:
    """``(width, height)`` in pixels, both at least 16.

    Raises
    ------
    ValueError
        Naming the size given.
    """
    size = tuple(int(s) for s in np.ravel(size))
    if len(size) != 2 or min(size) < 16:
        raise ValueError(f"size must be (width, height) with both at least 16 pixels, got {size}")
    return size


class OffscreenRenderer:
    """The backend choice, the drawing thread and the fallback of a renderer.

    Subclasses set ``V`` (the rest positions) and ``size``, call
    :meth:`_start_backend` at the end of their ``__init__``, and implement
    ``_render_pyvista(U)`` and ``_render_matplotlib(U)``, each of which keeps
    its scene in ``self._scene`` (a pyvista scene's first item is its plotter).

    Attributes
    ----------
    backend : str
        ``"pyvista"`` (EGL) or ``"matplotlib"``; it becomes ``"matplotlib"``
        for good if a pyvista render fails.
    """

    def _start_backend(self) -> None:
        self.backend = "pyvista" if plotting._use_pyvista() else "matplotlib"
        self._scene = None
        self._gl_thread = None

    def render(self, U):
        """The picture of the mesh at positions ``U``.

        Parameters
        ----------
        U : array_like of float
            Deformed positions, the shape of ``V``.

        Returns
        -------
        (height, width, 3) numpy.ndarray of uint8
            RGB.
        """
        U = as_float_array(U, "U", ndim=2)
        if U.shape != self.V.shape:
            raise ValueError(f"U must have the shape of V {self.V.shape}, got {U.shape}")
        name = type(self).__name__
        if self.backend == "pyvista":
            if self._gl_thread is None:
                self._gl_thread = ThreadPoolExecutor(max_workers=1, thread_name_prefix=name)
            try:
                return self._gl_thread.submit(self._render_pyvista, U).result()
            except Exception as exc:  # a driver that passed the check can still fail
                warnings.warn(f"{name}: pyvista failed ({type(exc).__name__}: {exc}); using matplotlib",
                              RuntimeWarning, stacklevel=2)
                self._gl_thread.shutdown(wait=False)
                self.backend, self._scene, self._gl_thread = "matplotlib", None, None
        return self._render_matplotlib(U)

    def encoded(self, U, format: str, **options) -> bytes:
        """:meth:`render` encoded by Pillow as ``format`` (``"png"``, ``"jpeg"``) with its ``options``."""
        from PIL import Image

        buffer = io.BytesIO()
        Image.fromarray(self.render(U)).save(buffer, format=format, **options)
        return buffer.getvalue()

    def close(self):
        """Release the off-screen window and its thread (the renderer builds new ones when used again)."""
        if self._gl_thread is not None:
            if self._scene is not None:
                self._gl_thread.submit(self._scene[0].close).result()
            self._gl_thread.shutdown()
        self._scene, self._gl_thread = None, None
