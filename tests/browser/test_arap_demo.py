"""The ARAP demo (libigl 405) in JupyterLab in headless Chromium: it runs all its cells without an
error and shows its widget and animation; dragging the bar's right end in the picture moves the
mesh with the mouse, and while the handles stay put the energy the widget shows never rises from
one frame to the next.

The server, the browser and the notebook driving are test_jupyterlab.py's and conftest.py's.
:func:`drag_and_record` is also what ``benchmarks/bench_arap_demo.py`` measures the frame rate with.
"""

from __future__ import annotations

import contextlib
import re
from pathlib import Path

import nbformat
import numpy as np
import pytest

from starter.meshes import load_handles, load_mesh

from .conftest import CHROMIUM, NO_CHROMIUM, jupyter_env, jupyter_server
from .test_jupyterlab import PANEL, SETTINGS, Lab, drawn_fraction, element_picture, errors, run_all_cells, unexecuted

if not CHROMIUM.is_file():
    pytest.skip(NO_CHROMIUM, allow_module_level=True)
sync_api = pytest.importorskip("playwright.sync_api", reason="the playwright package (the dev extra) is not installed")

# Running the demo (a GIF, a scripted drag, settling twice) takes a minute or two on a busy 2-core machine.
pytestmark = [pytest.mark.slow, pytest.mark.timeout(600)]

DEMO = "demo_arap"
# frame 12 (handles still) · ARAP energy 0.276179133 · 1.0 iterations/frame · 31.2 frames/s ...
LABEL = re.compile(r"^frame (\d+) \(handles (moved|still)\) · ARAP energy (\S+) · ([\d.]+) iterations/frame · ([\d.]+) frames/s")
# Every new picture and every new label, with the page's clock: MutationObserver records each text
# node the label gets, so frames that arrive together are all kept.
RECORD = """([image, label]) => {
  window.__arap = {sources: [], labels: []};
  new MutationObserver(() => window.__arap.sources.push(performance.now()))
    .observe(image, {attributes: true, attributeFilter: ['src']});
  new MutationObserver((records) => {
    for (const r of records) for (const n of r.addedNodes) window.__arap.labels.push([performance.now(), n.textContent]);
  }).observe(label, {childList: true, subtree: true, characterData: false});
}"""


@contextlib.contextmanager
def serve_demo(workdir: Path):
    """JupyterLab on 127.0.0.1 serving the ARAP demo as the student bundle ships it, pictures on."""
    from grader.build.release import demo_notebook
    from grader.paths import CoursePaths

    root = workdir / "served"
    root.mkdir()
    for name, text in SETTINGS.items():
        path = workdir / "settings" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    course = CoursePaths(workdir / "course")
    course.root.mkdir()
    course.notebooks.symlink_to(Path(__file__).resolve().parents[2] / "notebooks", target_is_directory=True)
    nbformat.write(demo_notebook(course, DEMO), root / f"{DEMO}.ipynb")
    env = jupyter_env(workdir)
    env.update(JUPYTERLAB_SETTINGS_DIR=str(workdir / "settings"), JUPYTERLAB_WORKSPACES_DIR=str(workdir / "workspaces"))
    args = ["--LabApp.news_url=None", "--LabApp.check_for_updates_class=jupyterlab.handlers.announcements.NeverCheckForUpdate"]
    with jupyter_server("lab", root, workdir / "jupyterlab.log", env, args) as server:
        yield Lab(server.url, server.token, server.log, root)


def right_end_pixel(size=(560, 360)) -> np.ndarray:
    """Where the widget's default view shows the centre of the bar's right end at rest."""
    from starter.arap_widget import ArapRenderer

    V, F = load_mesh("bar_fine")
    ends = load_handles("bar_fine")
    return ArapRenderer(V, F, [ends["left"], ends["right"]], size).to_pixels(V[ends["right"]].mean(axis=0)[None])[0]


def widget_parts(page):
    """The demo widget's picture and its label (the one reading ``frame N ...``)."""
    image = page.locator(f"{PANEL} .widget-image").first
    label = page.locator(f"{PANEL} .widget-label-basic, {PANEL} .widget-label").filter(has_text=re.compile(r"^frame \d+")).first
    return image, label


def parse(labels) -> list[tuple]:
    """``(page ms, frame, moved, energy, iterations per frame, frames per second)`` of every label seen."""
    rows = []
    for at, text in labels:
        m = LABEL.match(text)
        if m:
            rows.append((at, int(m[1]), m[2] == "moved", float(m[3]), float(m[4]), float(m[5])))
    return rows


def drag_and_record(page, path_pixels, seconds: float, settle_s: float = 60.0, mark=None) -> dict:
    """Press on the first pixel of ``path_pixels``, move through the rest in ``seconds``, release, wait for
    the frames to settle; what the page saw.

    Returns
    -------
    dict
        ``drag_ms`` (page clock at the press and at the release), ``sources`` (page times of every new
        picture), ``frames`` (:func:`parse` of every label), ``marks`` (what ``mark()`` returned at the
        press and at the release, e.g. a process's CPU times).
    """
    mark = mark or (lambda: None)
    image, label = widget_parts(page)
    image.scroll_into_view_if_needed()
    box = image.bounding_box()
    scale = box["width"] / 560
    at = [(box["x"] + x * scale, box["y"] + y * scale) for x, y in path_pixels]
    page.evaluate(RECORD, [image.element_handle(), label.element_handle()])
    page.mouse.move(*at[0])
    page.mouse.down()
    pressed, marks = page.evaluate("performance.now()"), [mark()]
    pause = max(1, int(1000 * seconds / max(1, len(at) - 1)))
    for point in at[1:]:
        page.mouse.move(*point)
        page.wait_for_timeout(pause)
    page.mouse.up()
    released = page.evaluate("performance.now()")
    marks.append(mark())
    # Settled: the label reads "handles still" and no new label came for two seconds.
    quiet, last = 0, -1
    for _ in range(int(settle_s * 10)):
        page.wait_for_timeout(100)
        count = page.evaluate("window.__arap.labels.length")
        quiet = quiet + 1 if count == last else 0
        last = count
        if quiet >= 20 and "handles still" in label.inner_text():
            break
    seen = page.evaluate("window.__arap")
    return {"drag_ms": (pressed, released), "sources": seen["sources"], "frames": parse(seen["labels"]), "marks": marks}


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("arap-lab")
    with serve_demo(workdir) as server:
        yield server, workdir


def test_the_arap_demo_runs_in_jupyterlab_and_dragging_the_right_end_moves_the_mesh_with_falling_energy(lab, browser):
    server, workdir = lab
    page = browser.new_page()
    nb, shot = run_all_cells(page, server, DEMO, workdir)
    assert errors(nb) == [], f"screenshot: {shot}"
    assert unexecuted(nb) == [], f"cells left unexecuted; screenshot: {shot}"
    assert page.locator(f"{PANEL} .jp-OutputArea-output img[src^='data:image/gif']").count() == 1, f"no animation shown: {shot}"
    image, label = widget_parts(page)
    assert label.count() == 1, f"no frame label under the widget: {shot}"
    before_path = workdir / "arap-widget-before.png"
    before = element_picture(image, before_path)
    assert 0.05 < drawn_fraction(before) < 0.7, f"the widget shows no bar: {before_path} (page: {shot})"

    # Drag the right end 90 pixels up, in 30 moves over 1.5 s.
    start = right_end_pixel()
    seen = drag_and_record(page, [start + [0.0, -3.0 * k] for k in range(31)], seconds=1.5)
    after_path = workdir / "arap-widget-dragged.png"
    after = element_picture(image, after_path)
    frames = seen["frames"]
    assert frames, f"no frame label arrived during the drag; page: {after_path}"
    assert any(moved for _, _, moved, *_ in frames), f"no frame followed the moving handle: {frames[:5]}"
    changed = float((np.abs(after.astype(int) - before.astype(int)).max(axis=-1) > 30).mean())
    assert changed > 0.01, f"only {changed:.2%} of the picture changed: {before_path} vs {after_path}"

    # The right end (blue) is where the mouse let go: 90 pixels up.
    def blue_centre(img):
        r, g, b = np.moveaxis(img.astype(int), -1, 0)
        rows, cols = np.nonzero((b > r + 60) & (b > g + 25))
        return np.array([cols.mean(), rows.mean()]) * 560 / img.shape[1]

    shift = blue_centre(after) - blue_centre(before)
    assert abs(shift[0]) < 8 and abs(shift[1] + 90) < 8, f"the right end moved by {shift} pixels: {after_path}"

    # At still handles every frame lowers the energy (or keeps it, once converged to the digits shown).
    still = [(a, b) for a, b in zip(frames, frames[1:]) if not b[2] and b[1] == a[1] + 1]
    assert len(still) >= 3, f"only {len(still)} consecutive frames at still handles: {frames[-5:]}"
    rises = [(a[1], a[3], b[3]) for a, b in still if b[3] > a[3] * (1 + 1e-8)]
    assert rises == [], f"the energy rose between frames at still handles (frame, before, after): {rises}"
    last_move = max(k for k, f in enumerate(frames) if f[2])
    settling = frames[last_move:]
    assert len(settling) >= 3 and settling[-1][3] < settling[0][3], f"the energy did not fall after the drag: {settling}"
    page.close()
