"""starter.video.write_mp4: what is written decodes back to the frames, at their rate and size."""

import sys
from fractions import Fraction

import av
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from starter.video import write_mp4


def moving_square(k, height, width):
    frames = np.full((k, height, width, 3), 255, np.uint8)
    for i in range(k):
        x = (7 * i) % max(1, width - 20)
        frames[i, height // 4: height // 2, x: x + 20] = [200, 30, 30]
    return frames


def psnr(a, b):
    """Peak signal-to-noise ratio in dB of 8-bit pictures (infinite when equal)."""
    mse = np.mean((np.asarray(a, float) - np.asarray(b, float)) ** 2)
    return np.inf if mse == 0 else 10 * np.log10(255**2 / mse)


def decode(path):
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        info = stream.codec_context.name, stream.width, stream.height, stream.average_rate
        return info, np.array([frame.to_ndarray(format="rgb24") for frame in container.decode(video=0)])


@settings(max_examples=8, deadline=None)
@given(k=st.integers(1, 15), height=st.integers(32, 120), width=st.integers(32, 120))
def test_every_frame_decodes_back_close_to_what_was_drawn_with_odd_sides_padded(tmp_path_factory, k, height, width):
    path = tmp_path_factory.mktemp("video") / "square.mp4"
    frames = moving_square(k, height, width)
    assert write_mp4(path, frames, fps=24) == k
    (codec, w, h, rate), decoded = decode(path)
    assert (codec, w, h, rate) == ("h264", width + width % 2, height + height % 2, 24)
    assert decoded.shape == (k, h, w, 3)
    assert psnr(decoded[:, :height, :width], frames) >= 30  # quality 18 in 4:2:0 blurs sharp colour edges a little
    # the padding copies the edge
    assert psnr(decoded[:, :height, -1], decoded[:, :height, w - 1 - width % 2]) >= 30


def test_ntsc_rates_are_stored_as_exact_fractions(tmp_path):
    write_mp4(tmp_path / "ntsc.mp4", moving_square(3, 32, 32), fps=30000 / 1001)
    (_, _, _, rate), _ = decode(tmp_path / "ntsc.mp4")
    assert rate == Fraction(30000, 1001)


@pytest.mark.parametrize(
    "frames, kwargs, message",
    [
        (moving_square(2, 32, 32).astype(float), {}, "frame 0 must be an (h, w, 3) uint8 RGB array"),
        (list(moving_square(2, 32, 32)) + [moving_square(1, 32, 34)[0]], {}, "frame 2 is 34x32, the first was 32x32"),
        ([], {}, "no frames to write"),
        (moving_square(2, 32, 32)[..., :2], {}, "frame 0 must be an (h, w, 3)"),
        (moving_square(2, 32, 32), {"fps": 0}, "fps must be positive and finite"),
        (moving_square(2, 32, 32), {"fps": float("nan")}, "fps must be positive and finite"),
        (moving_square(2, 32, 32), {"quality": 60}, "quality must be a constant rate factor from 0 to 51"),
    ],
)
def test_bad_frames_or_settings_are_refused_and_leave_an_existing_file_untouched(tmp_path, frames, kwargs, message):
    path = tmp_path / "kept.mp4"
    path.write_bytes(b"an earlier video")
    with pytest.raises(ValueError) as error:
        write_mp4(path, frames, **{"fps": 10, **kwargs})
    assert message in str(error.value)
    assert path.read_bytes() == b"an earlier video"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.mp4"]  # no partial file is left behind


def test_without_pyav_the_error_says_what_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "av", None)  # what an environment without the package looks like to import
    with pytest.raises(ImportError, match=r"MP4 export needs PyAV: pip install av"):
        write_mp4(tmp_path / "a.mp4", moving_square(1, 16, 16), fps=10)
    assert not (tmp_path / "a.mp4").exists()
