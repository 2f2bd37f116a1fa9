"""The feedback page's interactive view in headless Chromium: it draws, one drag turns both cameras, nothing goes out.

Debian's ``/usr/bin/chromium`` driven by playwright, as in conftest.py; the page is a real feedback page
(``grader.pipeline.feedback.feedback_html``) of planted outputs on the hidden cases, opened from disk.
Screenshots are saved beside the page and named in assertion messages.
"""

from __future__ import annotations

import io
import socket
import threading

import nbformat
import numpy as np
import pytest
from PIL import Image

from grader.harness.outputs import CaseOutput, Collected
from grader.pipeline.feedback import feedback_html
from grader.pipeline.unit import UnitSpec
from grader.pipeline.verify import GradedCell, hidden_cases, verify

SEED = 11
# Seconds in all, but a busy machine may be slow to start Chromium.
pytestmark = pytest.mark.timeout(180)


def drawn_fraction(png: bytes) -> float:
    """Share of pixels that differ clearly from the white background."""
    pixels = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    return float((np.abs(pixels - 255).max(axis=-1) > 30).mean())


def pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def moved_by_031(function, dims=(2, 3)):
    """The reference's output with vertex 3 moved by 0.31 on cases in ``dims`` dimensions; the others raised."""
    def output(case, ref):
        if np.shape(case.steps[0].args[0])[1] not in dims:
            return None
        value = np.array(ref, float)
        value[3] += 0.31
        return value
    return output


def feedback_page(path, outputs: dict) -> str:
    """Write the feedback page of functions whose hidden cases returned ``outputs[function](case, ref)``."""
    results = []
    for function, output in outputs.items():
        cases, expected = hidden_cases(function, SEED)
        values = [output(c, r) for c, r in zip(cases, expected)]
        collected = Collected(function, [CaseOutput(v, None if v is not None else "ValueError: planted", 0.1) for v in values], None)
        results.append((GradedCell(f"test_{function}", function, 4.0), verify(function, SEED, collected, None), collected))
    spec = UnitSpec(student_id="ada", notebook="03_arap", submission=b"{}", source=nbformat.writes(nbformat.v4.new_notebook()), seed=SEED)
    path.write_text(feedback_html(spec, results, []))
    return path.as_uri()


class Listener:
    """A TCP listener on 127.0.0.1 counting the connections it accepts."""

    def __init__(self):
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.connections = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self):
        while not self._stop.is_set():
            try:
                conn, _ = self.sock.accept()
            except (TimeoutError, OSError):
                continue
            self.connections += 1
            conn.close()

    def close(self):
        self._stop.set()
        self._thread.join()
        self.sock.close()


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    folder = tmp_path_factory.mktemp("feedback-view")
    flat = feedback_page(folder / "flat.html", {"laplacian_editing": moved_by_031("laplacian_editing", (2,)),
                                                "bbw": moved_by_031("bbw")})
    solid = feedback_page(folder / "solid.html", {"laplacian_editing": moved_by_031("laplacian_editing", (3,))})
    return folder, flat, solid


@pytest.fixture
def opened(browser, pages):
    """``open(url) -> (page, problems, requests)``: a page loaded and drawn, its console problems and every request
    the browser sent for it (from the DevTools protocol's Network domain)."""
    opened_pages = []

    def open_(url):
        page = browser.new_page()
        opened_pages.append(page)
        problems, requests = [], []
        page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}") if m.type in ("error", "warning") else None)
        page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
        cdp = browser.new_cdp_session(page)
        cdp.on("Network.requestWillBeSent", lambda event: requests.append(event["request"]["url"]))
        cdp.send("Network.enable")
        page.goto(url)
        page.wait_for_function("""() => [...document.querySelectorAll('canvas.dl-pane')].every(c => c.getAttribute('data-camera'))""",
                               timeout=20_000)
        return page, problems, requests

    yield open_
    for page in opened_pages:
        page.close()


def outside(requests: list[str]) -> list[str]:
    """The requests for anything but the page's own data: URLs (its pictures)."""
    return [url for url in requests if not url.startswith("data:")]


def settled(page) -> None:
    """Wait until the views have drawn what the last input asked for (they draw on the next animation frame)."""
    page.evaluate("() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")


def camera(canvas) -> list[float]:
    return [float(x) for x in canvas.get_attribute("data-camera").split()]


def test_the_views_draw_both_meshes_offline_without_error(opened, pages):
    folder, flat, solid = pages
    for url, views in ((flat, 2), (solid, 1)):
        page, problems, requests = opened(url)
        shot = folder / f"{url.rsplit('/', 1)[1]}.png"
        page.screenshot(path=str(shot), full_page=True)
        assert problems == [], f"screenshot: {shot}"
        assert outside(requests) == [url], f"requests: {outside(requests)}; screenshot: {shot}"
        assert page.locator("section.dl-view .dl-interactive:not([hidden])").count() == views, f"screenshot: {shot}"
        canvases = page.locator("canvas.dl-pane")
        assert canvases.count() == 2 * views
        for k in range(canvases.count()):
            fraction = drawn_fraction(canvases.nth(k).screenshot())
            assert 0.02 < fraction < 0.9, f"canvas {k} of {url}: {fraction:.3f} drawn; screenshot: {shot}"
        descriptions = page.locator(".dl-description")
        assert descriptions.count() == views and "vertex 3" in descriptions.first.inner_text()


def test_dragging_one_view_turns_both_cameras_the_same_way_and_the_wheel_zooms_both(opened, pages):
    folder, flat, solid = pages
    page, problems, _ = opened(solid)
    left, right = page.locator("section.dl-view canvas.dl-pane").all()
    start = camera(left)
    assert camera(right) == start
    before = pixels(right.screenshot())
    left.scroll_into_view_if_needed()
    box = left.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 60, y + 20, steps=6)
    page.mouse.up()
    settled(page)
    turned = camera(left)
    assert camera(right) == turned, "both views share one camera"
    assert turned[0] == pytest.approx(start[0] + 0.6, abs=1e-3) and turned[1] == pytest.approx(start[1] + 0.2, abs=1e-3)
    assert turned[2] == start[2]
    shot = folder / "solid-turned.png"
    after = pixels(right.screenshot(path=str(shot)))
    assert np.abs(after - before).max(axis=-1).astype(bool).mean() > 0.01, f"the reference's view did not turn; screenshot: {shot}"

    right.hover()
    page.mouse.wheel(0, -300)
    settled(page)
    zoomed = camera(right)
    assert camera(left) == zoomed and zoomed[2] > turned[2] and zoomed[:2] == turned[:2]
    assert problems == []


def test_a_drag_in_one_view_leaves_the_other_cases_views_alone_and_the_colour_menu_switches_fields(opened, pages):
    folder, flat, _ = pages
    page, problems, _ = opened(flat)
    first, weights = page.locator("section.dl-view").all()
    canvas = first.locator("canvas.dl-pane").first
    untouched = [camera(c) for c in weights.locator("canvas.dl-pane").all()]
    canvas.scroll_into_view_if_needed()
    box = canvas.bounding_box()
    page.mouse.move(box["x"] + 100, box["y"] + 100)
    page.mouse.down()
    page.mouse.move(box["x"] + 150, box["y"] + 100, steps=5)
    page.mouse.up()
    settled(page)
    assert camera(canvas) != untouched[0] and [camera(c) for c in weights.locator("canvas.dl-pane").all()] == untouched

    legends = weights.locator(".dl-legend")
    assert [legends.nth(k).is_visible() for k in range(legends.count())] == [True] + [False] * (legends.count() - 1)
    pane = weights.locator("canvas.dl-pane").first
    before = pixels(pane.screenshot())
    weights.locator("select.dl-field").select_option("1")
    settled(page)
    assert [legends.nth(k).is_visible() for k in range(legends.count())] == [False, True] + [False] * (legends.count() - 2)
    assert "weight of handle 1" in legends.nth(1).inner_text()
    shot = folder / "flat-weight-1.png"
    assert np.abs(pixels(pane.screenshot(path=str(shot))) - before).max(axis=-1).astype(bool).mean() > 0.05, f"screenshot: {shot}"
    assert problems == []


def test_the_page_cannot_connect_anywhere(opened, pages):
    _, flat, _ = pages
    page, _, requests = opened(flat)
    settled(page)
    assert outside(requests) == [flat], f"the page itself requested {outside(requests)}"
    # Planted attempts (from DevTools, as a student's content would try): the page's policy stops both.
    listener = Listener()
    try:
        outcome = page.evaluate(
            """(url) => new Promise((resolve) => {
                   const violations = [];
                   document.addEventListener('securitypolicyviolation', (e) => violations.push(e.violatedDirective));
                   fetch(url).then(() => resolve(['fetched', violations]), () => setTimeout(() => resolve(['blocked', violations]), 100));
               })""",
            f"http://127.0.0.1:{listener.port}/",
        )
        image = page.evaluate(
            """(url) => new Promise((resolve) => {
                   const img = new Image();
                   img.onload = () => resolve('loaded');
                   img.onerror = () => resolve('blocked');
                   img.src = url;
                   document.body.appendChild(img);
               })""",
            f"http://127.0.0.1:{listener.port}/x.png",
        )
    finally:
        listener.close()
    assert outcome == ["blocked", ["connect-src"]]
    assert image == "blocked"
    assert listener.connections == 0
