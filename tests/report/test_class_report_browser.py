"""The class report in headless Chromium: it opens from disk with no network, no console error, and every plot is drawn.

Debian's ``/usr/bin/chromium`` driven by the ``playwright`` package's bundled driver, as in tests/browser;
screenshots are saved beside the report and named in every assertion message.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from grader.report.class_report import write_class_report

CHROMIUM = Path("/usr/bin/chromium")
if not CHROMIUM.is_file():
    pytest.skip(f"Debian's chromium is not installed ({CHROMIUM} is missing): `make test` installs it when run as root",
                allow_module_level=True)
sync_api = pytest.importorskip("playwright.sync_api", reason="the playwright package (the dev extra) is not installed")

pytestmark = [pytest.mark.slow, pytest.mark.timeout(300)]

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]


def drawn_fraction(img: np.ndarray) -> float:
    """Share of pixels that differ clearly from the white background."""
    return float((np.abs(img.astype(int) - 255).max(axis=-1) > 30).mean())


def test_the_report_renders_offline_with_drawn_plots_and_no_console_error(graded_class, tmp_path_factory):
    _, _, out, _ = graded_class
    page_path = write_class_report(out)
    shots = tmp_path_factory.mktemp("report-shots")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
        try:
            page = browser.new_page(viewport={"width": 1300, "height": 900})
            problems, requests = [], []
            page.on("console", lambda m: problems.append(f"console {m.type}: {m.text}") if m.type in ("error", "warning") else None)
            page.on("pageerror", lambda e: problems.append(f"page error: {e}"))
            page.on("request", lambda r: requests.append(r.url))
            page.goto(page_path.as_uri())
            page.wait_for_load_state("load")
            full = shots / "report.png"
            page.screenshot(path=str(full), full_page=True)
            assert problems == [], f"screenshot: {full}"
            assert all(url.startswith(("file:", "data:")) for url in requests), f"network requests: {requests}"
            images = page.locator("figure img")
            assert images.count() == 3, f"screenshot: {full}"
            for k in range(images.count()):
                image = images.nth(k)
                assert image.evaluate("(img) => img.complete && img.naturalWidth > 0"), f"plot {k} not decoded; screenshot: {full}"
                shot = shots / f"plot-{k}.png"
                pixels = np.asarray(Image.open(io.BytesIO(image.screenshot(path=str(shot)))).convert("RGB"))
                assert pixels.shape[1] >= 600, f"plot {k} is {pixels.shape[1]} px wide; screenshot: {shot}"
                assert drawn_fraction(pixels) > 0.02, f"plot {k} is empty; screenshot: {shot}"
        finally:
            browser.close()
