"""The pictures of docs/, taken by the browser tests once they have checked what they show.

``BELVEDERE_DOCS_SCREENSHOTS=docs/images python -m pytest -m browser tests/viewer`` writes
them (a relative directory is taken from the repository's root); without the variable the
tests take none.
"""

from __future__ import annotations

import os
from io import BytesIO
from pathlib import Path
from typing import Any

__all__ = ["DOCS_SCREENSHOTS", "docs_screenshot"]

DOCS_SCREENSHOTS = "BELVEDERE_DOCS_SCREENSHOTS"
ROOT = Path(__file__).resolve().parents[2]
SETTLE = 1.0
"""Seconds for the browser to draw the updates that followed the checked ones (the scan's
next sweep, a slider's label): the picture shows a scene at rest, not one frame in."""
COLOURS = 128
"""A palette this size keeps the viewer's flat shading and text, at a fifth of the bytes."""


def docs_screenshot(page: Any, name: str) -> Path | None:
    """With ``BELVEDERE_DOCS_SCREENSHOTS=DIR``: the page as ``DIR/<name>.png``, its path.

    ``page`` comes from ``browser_page``, which hides the test browser's software-WebGL notice
    (not what a user's browser with a GPU shows)."""
    directory = os.environ.get(DOCS_SCREENSHOTS)
    if not directory:
        return None
    from PIL import Image

    page.wait_for_timeout(SETTLE * 1000)
    image = Image.open(BytesIO(page.screenshot())).convert("RGB")
    path = ROOT / directory / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    image.quantize(colors=COLOURS, dither=Image.Dither.NONE).save(path, optimize=True)
    return path
