"""Write rendered frames as an H.264 MP4 video.

PyAV (``pip install av``, or the ``deformlab[video]`` extra) is needed; its
wheel carries its own FFmpeg build, so nothing is installed system-wide.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import numpy as np

MISSING_PYAV = "MP4 export needs PyAV: pip install av (or the deformlab[video] extra); a .gif needs nothing more"


def write_mp4(path, frames, fps, quality=18):
    """Encode RGB frames as an H.264 MP4 that browsers and slide software play.

    The file appears only once it is complete: the video is written beside it
    under a temporary name, then renamed.

    Parameters
    ----------
    path : str or os.PathLike
        Target file.
    frames : iterable of (h, w, 3) uint8 numpy.ndarray
        RGB frames, all of one size. H.264 in 4:2:0 needs even sides, so an
        odd width or height gains one column or row copied from its edge.
    fps : float
        Frames per second; stored as a fraction, so 30000/1001 is exact.
    quality : int
        x264's constant rate factor, 0 (lossless) to 51; 18 looks lossless.

    Returns
    -------
    int
        The number of frames written.
    """
    try:
        import av
    except ImportError as error:
        raise ImportError(MISSING_PYAV) from error
    fps = float(fps)
    if not np.isfinite(fps) or fps <= 0:
        raise ValueError(f"fps must be positive and finite, got {fps}")
    if not 0 <= int(quality) <= 51:
        raise ValueError(f"quality must be a constant rate factor from 0 to 51, got {quality}")
    path = Path(path)
    partial = path.with_name(f".{path.name}.partial")
    count, size = 0, None
    try:
        with av.open(str(partial), mode="w", format="mp4", options={"movflags": "+faststart"}) as container:
            stream = container.add_stream("libx264", rate=Fraction(fps).limit_denominator(100_000))
            stream.pix_fmt = "yuv420p"
            stream.options = {"crf": str(int(quality))}
            for frame in frames:
                frame = np.asarray(frame)
                if frame.dtype != np.uint8 or frame.ndim != 3 or frame.shape[2] != 3:
                    raise ValueError(f"frame {count} must be an (h, w, 3) uint8 RGB array, got {frame.dtype} {frame.shape}")
                if size is None:
                    size = frame.shape[:2]
                    stream.height, stream.width = (side + side % 2 for side in size)
                elif frame.shape[:2] != size:
                    raise ValueError(f"frame {count} is {frame.shape[1]}x{frame.shape[0]}, the first was {size[1]}x{size[0]}")
                even = np.pad(frame, ((0, size[0] % 2), (0, size[1] % 2), (0, 0)), mode="edge")
                container.mux(stream.encode(av.VideoFrame.from_ndarray(even, format="rgb24")))
                count += 1
            if count == 0:
                raise ValueError("no frames to write")
            container.mux(stream.encode())
        os.replace(partial, path)
    finally:
        partial.unlink(missing_ok=True)
    return count
