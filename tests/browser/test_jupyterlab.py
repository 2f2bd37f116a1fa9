"""JupyterLab in headless Chromium: a release notebook filled with the reference solutions and the
skinning demo run all their cells, show no error and show the rendered mesh; dragging a bone's tip
in the demo's picture turns that bone, and dragging a slider redraws the character.

The browser and the server are conftest.py's (Debian's Chromium; loopback, random token); JupyterLab
serves a temporary folder; screenshots are saved under the fixture's temporary folder and named in
every assertion message.
"""

from __future__ import annotations

import io
import json
import re
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path

import nbformat
import numpy as np
import pytest
from PIL import Image

from starter.meshes import load_handles, load_mesh
from starter.skinning_widget import SkinRenderer

from .conftest import CHROMIUM, NO_CHROMIUM, Server, jupyter_env, jupyter_server

if not CHROMIUM.is_file():
    pytest.skip(NO_CHROMIUM, allow_module_level=True)
sync_api = pytest.importorskip("playwright.sync_api", reason="the playwright package (the dev extra) is not installed")

pytestmark = [pytest.mark.slow, pytest.mark.timeout(300)]

ROOT = Path(__file__).resolve().parents[2]
RELEASE_NOTEBOOK = "05_lbs"
DEMO = "demo_skinning"
# JupyterLab settings for a quiet, deterministic page: no news or update toasts; every cell in the DOM;
# the notebook's kernel starts without a "Select Kernel" dialog (Lab opens one when the kernel specs
# load after the notebook, as on a busy machine, and that dialog swallows the clicks on the Run menu).
SETTINGS = {
    "@jupyterlab/apputils-extension/notification.jupyterlab-settings": '{"fetchNews": "false", "checkForUpdates": false}',
    "@jupyterlab/notebook-extension/tracker.jupyterlab-settings": '{"windowingMode": "none", "autoStartDefaultKernel": true}',
}
PANEL = ".jp-NotebookPanel:not(.lm-mod-hidden)"
# Every code cell shows an execution count and the kernel is idle. ("Idle and no [*]" alone was not
# enough: on a loaded machine it held when only the first cell had run.)
FINISHED = """(panel) => {
  const p = document.querySelector(panel);
  if (!p) return false;
  const status = p.querySelector('.jp-Notebook-ExecutionIndicator')?.dataset.status;
  const prompts = Array.from(p.querySelectorAll('.jp-CodeCell .jp-InputPrompt')).map(e => e.textContent.trim());
  return status === 'idle' && prompts.length > 0 && prompts.every(t => /^\\[\\d+\\]:$/.test(t));
}"""
RUN_TIMEOUT_MS = 120_000


@dataclass
class Lab(Server):
    root: Path = Path()


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("lab")


def fill(root: Path, workdir: Path) -> None:
    """Write what JupyterLab serves into ``root``: the release 05_lbs filled with the reference, and the demo."""
    from benchmarks.bench_grading import student_version
    from grader.build.authored import read_authored
    from grader.build.release import demo_notebook
    from grader.gradebook import generate_assignment
    from grader.build.source_notebook import build_source_notebook
    from grader.paths import CoursePaths

    course = CoursePaths(workdir / "course")
    course.root.mkdir()
    course.notebooks.symlink_to(ROOT / "notebooks", target_is_directory=True)
    source = course.source / "deformation" / f"{RELEASE_NOTEBOOK}.ipynb"
    source.parent.mkdir(parents=True)
    nbformat.write(build_source_notebook(read_authored(ROOT / "notebooks" / "deformation" / f"{RELEASE_NOTEBOOK}.py")), source)
    generate_assignment(course, "deformation", f"sqlite:///{workdir}/gradebook.db")
    released = course.release / "deformation" / source.name
    nbformat.write(student_version(source, released), root / source.name)
    nbformat.write(demo_notebook(course, DEMO), root / f"{DEMO}.ipynb")


@pytest.fixture(scope="module")
def lab(workdir):
    """JupyterLab on 127.0.0.1 serving :func:`fill`'s notebooks with pictures on, fresh settings and
    workspaces; shut down afterwards."""
    lab_root = workdir / "served"
    lab_root.mkdir()
    for name, text in SETTINGS.items():
        path = workdir / "settings" / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    env = jupyter_env(workdir)
    env.update(JUPYTERLAB_SETTINGS_DIR=str(workdir / "settings"), JUPYTERLAB_WORKSPACES_DIR=str(workdir / "workspaces"))
    args = ["--LabApp.news_url=None", "--LabApp.check_for_updates_class=jupyterlab.handlers.announcements.NeverCheckForUpdate"]
    with jupyter_server("lab", lab_root, workdir / "jupyterlab.log", env, args, while_starting=lambda: fill(lab_root, workdir)) as server:
        yield Lab(server.url, server.token, server.log, lab_root)


def dialogs(page) -> list[str]:
    """The text of every JupyterLab dialog open on the page (a kernel that died, a file changed on disk...)."""
    found = page.locator(".jp-Dialog")
    return [" ".join(found.nth(k).inner_text().split()) for k in range(found.count())]


def run_all_cells(page, lab: Lab, name: str, shots: Path):
    """Open ``name``.ipynb in its own workspace, Run > Run All Cells, wait for the kernel, save.

    Returns
    -------
    (NotebookNode, Path)
        The notebook as JupyterLab saved it, and a screenshot of the page.
    """
    page.goto(f"{lab.url}/lab/workspaces/{name}/tree/{name}.ipynb?token={lab.token}")
    # Run All before the notebook's kernel is up opens a kernel selector or starts a second kernel
    # that drops the queued cells (both seen on a loaded machine): wait for the server's session first.
    kernel = idle_kernel(lab, f"{name}.ipynb")
    page.wait_for_selector(f"{PANEL} .jp-Notebook-ExecutionIndicator[data-status='idle']", timeout=60_000)
    first_prompt = page.locator(f"{PANEL} .jp-CodeCell .jp-InputPrompt").first
    for attempt in range(3):
        # A click that lands while the freshly opened notebook is still settling can be lost: retry it.
        try:
            page.locator(".lm-MenuBar-itemLabel", has_text=re.compile(r"^Run$")).click()
            page.locator(".lm-Menu-itemLabel", has_text=re.compile(r"^Run All Cells$")).click()
        except sync_api.TimeoutError:
            pytest.fail(f"could not click Run > Run All Cells; dialogs open: {dialogs(page)}")
        try:
            page.wait_for_function("(el) => /\\[(\\*|\\d+)\\]/.test(el.textContent)", arg=first_prompt.element_handle(),
                                   polling=200, timeout=10_000)
            break
        except sync_api.TimeoutError:
            if attempt == 2:
                raise
    shot = shots / f"{name}.png"
    try:
        page.wait_for_function(FINISHED, arg=PANEL, polling=500, timeout=RUN_TIMEOUT_MS)
    except sync_api.TimeoutError:
        # A cell that raised stops Run All; a kernel that died leaves a dialog. Show what was on the page.
        page.screenshot(path=str(shot))
        shown = page.locator(f"{PANEL} .jp-OutputArea-output[data-mime-type='application/vnd.jupyter.stderr']")
        pytest.fail(f"{name} did not finish in {RUN_TIMEOUT_MS // 1000} s; dialogs: {dialogs(page)}; "
                    f"stderr shown: {[shown.nth(k).inner_text()[-300:] for k in range(shown.count())]}; "
                    f"screenshot: {shot}; server log:\n{lab.log_tail()}")
    page.screenshot(path=str(shot))
    assert idle_kernel(lab, f"{name}.ipynb") == kernel, f"{name}'s kernel was replaced while it ran; screenshot: {shot}"
    return saved(page, lab.root / f"{name}.ipynb"), shot


def idle_kernel(lab: Lab, path: str, timeout_s: float = 90.0) -> str:
    """The id of the kernel the server runs for notebook ``path``, once it is idle."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        with urllib.request.urlopen(f"{lab.url}/api/sessions?token={lab.token}", timeout=10) as answer:
            sessions = [s for s in json.load(answer) if s.get("path") == path and s.get("kernel")]
        if len(sessions) == 1 and sessions[0]["kernel"]["execution_state"] == "idle":
            return sessions[0]["kernel"]["id"]
        time.sleep(0.3)
    pytest.fail(f"no idle kernel for {path} within {timeout_s:.0f} s; sessions: {sessions}; server log:\n{lab.log_tail()}")


def saved(page, path: Path):
    """Save the open notebook and read back what JupyterLab wrote to ``path``.

    The server writes a notebook in place, so the file is read only once its tab is no longer dirty
    and it parses: a half-written file is never taken for the saved one.
    """
    before = path.stat().st_mtime_ns
    page.keyboard.press("Control+s")
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        page.wait_for_timeout(200)
        if path.stat().st_mtime_ns == before or page.locator(".lm-TabBar-tab.jp-mod-dirty").count():
            continue
        try:
            return nbformat.read(path, as_version=4)
        except (ValueError, nbformat.reader.NotJSONError):
            continue
    pytest.fail(f"JupyterLab did not save {path.name} within 30 s")


def errors(nb) -> list[str]:
    return [f"cell {i + 1}: {out.ename}: {out.evalue}" for i, cell in enumerate(nb.cells)
            for out in cell.get("outputs", []) if out.output_type == "error"]


def unexecuted(nb) -> list[int]:
    return [i + 1 for i, cell in enumerate(nb.cells) if cell.cell_type == "code" and cell.execution_count is None]


def element_picture(locator, path: Path) -> np.ndarray:
    """What the browser shows of one element, saved to ``path``, as an RGB array."""
    locator.scroll_into_view_if_needed()
    return np.asarray(Image.open(io.BytesIO(locator.screenshot(path=str(path)))).convert("RGB"))


def settled_source(page, image, quiet_s: float = 1.0, timeout_s: float = 30.0) -> str:
    """The picture's ``src`` once it has stopped changing for ``quiet_s`` (a drag redraws several times)."""
    source, since, deadline = image.get_attribute("src"), time.monotonic(), time.monotonic() + timeout_s
    while time.monotonic() - since < quiet_s and time.monotonic() < deadline:
        page.wait_for_timeout(100)
        now = image.get_attribute("src")
        if now != source:
            source, since = now, time.monotonic()
    return source


def drawn_fraction(img: np.ndarray) -> float:
    """Share of pixels that differ clearly from the white background."""
    return float((np.abs(img.astype(int) - 255).max(axis=-1) > 30).mean())


def test_a_release_notebook_filled_with_the_reference_runs_in_jupyterlab_and_shows_its_meshes(lab, browser, workdir):
    page = browser.new_page()
    nb, shot = run_all_cells(page, lab, RELEASE_NOTEBOOK, workdir)
    assert errors(nb) == [], f"screenshot: {shot}"
    assert unexecuted(nb) == [], f"cells left unexecuted; screenshot: {shot}"
    saved_pictures = sum("image/png" in out.get("data", {}) for cell in nb.cells for out in cell.get("outputs", []))
    images = page.locator(f"{PANEL} .jp-OutputArea-output img")
    assert saved_pictures >= 3 and images.count() == saved_pictures, f"{images.count()} images shown, {saved_pictures} saved; screenshot: {shot}"
    for k in range(images.count()):
        picture = workdir / f"{RELEASE_NOTEBOOK}-image-{k}.png"
        drawn = drawn_fraction(element_picture(images.nth(k), picture))
        # A mesh fills part of its panel: neither a blank picture nor one covered edge to edge.
        assert 0.05 < drawn < 0.8, f"image {k} has {drawn:.1%} non-background pixels: {picture} (page: {shot})"
    page.close()


def rest_bone_pixels(bone: int, size=(480, 480)) -> np.ndarray:
    """Where the demo's picture shows a bone's joint and tip in the rest pose (the widget's default view), (2, 2)."""
    V, F = load_mesh("character_fine")
    bones = load_handles("character_fine")["bones"]
    renderer = SkinRenderer(V, F, np.eye(len(bones))[np.zeros(len(V), dtype=int)], bones, size)
    return renderer.to_pixels(V[[bones[bone][0], bones[bone][-1]]])


def test_the_skinning_demo_runs_in_jupyterlab_and_dragging_a_bone_or_a_slider_redraws_the_character(lab, browser, workdir):
    page = browser.new_page()
    nb, shot = run_all_cells(page, lab, DEMO, workdir)
    assert errors(nb) == [], f"screenshot: {shot}"
    assert unexecuted(nb) == [], f"cells left unexecuted; screenshot: {shot}"
    assert page.locator(f"{PANEL} .jp-OutputArea-output img[src^='data:image/gif']").count() == 1, f"no animation shown: {shot}"
    image = page.locator(f"{PANEL} .widget-image").first
    before_path = workdir / f"{DEMO}-widget-before.png"
    before = element_picture(image, before_path)
    assert 0.05 < drawn_fraction(before) < 0.7, f"the widget shows no character: {before_path} (page: {shot})"

    readouts = page.locator(f"{PANEL} .widget-slider .widget-readout")
    assert [readouts.nth(k).inner_text().strip() for k in range(7)] == ["0"] * 7, f"the demo ends in the rest pose; page: {shot}"

    # Drag the left arm's tip upwards in the picture: the arm turns to follow the mouse.
    source = image.get_attribute("src")
    box = image.bounding_box()
    scale = box["width"] / 480
    joint, tip = rest_bone_pixels(1)
    target = tip + [20.0, -90.0]
    page.mouse.move(box["x"] + tip[0] * scale, box["y"] + tip[1] * scale)
    page.mouse.down()
    page.mouse.move(box["x"] + target[0] * scale, box["y"] + target[1] * scale, steps=10)
    page.mouse.up()
    # The arm turns about its joint to point where the mouse was released (pixel y points down, mesh
    # y up); the slider holds whole degrees. Moves are throttled, so wait for the release's pose.
    (ax, ay), (bx, by) = (tip - joint) * [1, -1], (target - joint) * [1, -1]
    wanted = np.degrees(np.arctan2(ax * by - ay * bx, ax * bx + ay * by))
    arm = readouts.nth(1)
    try:
        page.wait_for_function("([el, wanted]) => Math.abs(Number(el.textContent.trim().replace('\u2212', '-')) - wanted) <= 1",
                               arg=[arm.element_handle(), float(wanted)], timeout=30_000)
        page.wait_for_function("([el, src]) => el.getAttribute('src') !== src", arg=[image.element_handle(), source],
                               timeout=30_000)
    except sync_api.TimeoutError:
        pass  # the assertions below say what was shown instead
    settled_source(page, image)
    dragged_path = workdir / f"{DEMO}-widget-arm-dragged.png"
    dragged = element_picture(image, dragged_path)
    turned = int(arm.inner_text().strip().replace("\u2212", "-"))  # the readout writes U+2212 for minus
    assert abs(turned - wanted) <= 1, f"left arm turned {turned}°, the mouse asked for {wanted:.1f}°: {dragged_path}"
    assert [readouts.nth(k).inner_text().strip() for k in (0, 2, 3, 4, 5, 6)] == ["0"] * 6, f"only the left arm moves: {dragged_path}"
    changed = float((np.abs(dragged.astype(int) - before.astype(int)).max(axis=-1) > 30).mean())
    assert changed > 0.005, f"only {changed:.2%} of the picture changed: {before_path} vs {dragged_path}"

    readout = readouts.first
    before, before_path = dragged, dragged_path
    source = image.get_attribute("src")
    handle = page.locator(f"{PANEL} .widget-slider .noUi-handle").first
    box = handle.bounding_box()
    y = box["y"] + box["height"] / 2
    page.mouse.move(box["x"] + box["width"] / 2, y)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] / 2 + 25, y, steps=5)
    page.mouse.up()
    page.wait_for_function("([el, src]) => el.getAttribute('src') !== src", arg=[image.element_handle(), source],
                           timeout=30_000)
    page.wait_for_function(FINISHED, arg=PANEL, polling=200, timeout=30_000)
    settled_source(page, image)
    after_path = workdir / f"{DEMO}-widget-after.png"
    after = element_picture(image, after_path)
    moved = workdir / f"{DEMO}-moved.png"
    page.screenshot(path=str(moved))
    assert readout.inner_text().strip() != "0", f"the spine slider did not move: {moved}"
    assert 0.05 < drawn_fraction(after) < 0.7, f"the widget shows no character after the drag: {after_path}"
    changed = float((np.abs(after.astype(int) - before.astype(int)).max(axis=-1) > 30).mean())
    assert changed > 0.01, f"only {changed:.2%} of the picture changed: {before_path} vs {after_path}"
    page.close()
