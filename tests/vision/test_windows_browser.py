"""A headless script's cv2 window in the viewer, in a real browser (Debian's Chromium): the
script, run as belvedere runs scripts, shows a picture of three coloured bands with
cv2.imshow; the viewer, beside it on the graph and asked for nothing, opens a panel titled
with the window's name showing those bands; keys typed into the panel's key field (and its
Esc button) are what the script's cv2.waitKey returns; cv2.destroyAllWindows takes the
panel away."""

from __future__ import annotations

from io import BytesIO
from pathlib import Path

import numpy as np
import pytest

from belvedere.graph import Graph, ZenohTransport
from belvedere.viewer import Viewer
from tests.conftest import free_port
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.test_browser import browser_page, view_centre
from tests.vision.window_script import PICTURE_BGR, WINDOW, WindowScript
from tests.waiting import wait_until

pytestmark = pytest.mark.browser

JPEG_TOLERANCE = 40
"""The panel's picture travels as JPEG: a band's colour comes back within this of each
channel (a wrong band is off by 255 in two)."""


def _bands(shot: bytes) -> list[tuple[int, int, int]]:
    """The colours at the middle of the picture's left, middle and right thirds."""
    from PIL import Image

    pixels = np.asarray(Image.open(BytesIO(shot)).convert("RGB")).astype(int)
    height, width = pixels.shape[:2]
    return [
        (int(r), int(g), int(b))
        for r, g, b in (pixels[height // 2, width * (2 * i + 1) // 6] for i in range(3))
    ]


def test_a_scripts_window_is_a_viewer_panel_that_takes_keys(endpoint: str, tmp_path: Path) -> None:
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    viewer = Viewer(graph, port=free_port())
    graph.start(rtf=None)
    script = WindowScript(tmp_path, count=5, destroy=True)
    try:
        with browser_page(viewer.url) as page:
            tab = page.get_by_text(WINDOW, exact=True)  # as the script spelled it
            tab.first.wait_for()
            picture = page.locator("img[src^='blob:']")
            picture.first.wait_for()
            assert picture.count() == 1
            expected = [bgr[::-1] for bgr in PICTURE_BGR]
            shown = _bands(picture.first.screenshot())
            for got, want in zip(shown, expected, strict=True):
                assert max(abs(g - w) for g, w in zip(got, want, strict=True)) < JPEG_TOLERANCE, (
                    shown
                )
            docs_screenshot(page, "cv2_window")
            page.mouse.click(*view_centre())
            page.keyboard.press("w")  # the 3D view's (viser moves its camera), not the window's
            picture.first.click()
            page.keyboard.press("q")
            page.keyboard.press("Escape")
            script.wait_for("key: 27")
            keys = page.locator("textarea:visible")
            assert keys.count() == 1
            keys.click()
            page.keyboard.type("a")
            page.keyboard.press("Enter")
            script.wait_for("key: 13")
            page.get_by_role("button", name="Esc", exact=True).click()
            assert script.wait_for("destroyed:") == "destroyed: -1"
            assert [line for line in script.lines if line.startswith("key:")] == [
                "key: 113",
                "key: 27",
                "key: 97",
                "key: 13",
                "key: 27",
            ]
            picture.first.wait_for(state="detached")
            wait_until(lambda: tab.count() == 0, what="the window's panel to go")
            assert not viewer.windows.windows
    finally:
        script.stop()
        viewer.close()
        graph.shutdown()
