"""Debian's Chromium as the browser tests and the viewer's frame-rate benchmark run it:
headless, WebGL in software (SwiftShader: no GPU on a CI runner), nothing fetched in the
background. One command line, so the frame rate the benchmark measures is that of the
browser the tests check.

WebGL's antialiasing is off, as rviz's ``--disable-anti-aliasing`` turns it off where
rendering is in software: SwiftShader resolves 4 samples a pixel on the CPU, and with it the
viewer's frame under load cost 1.1-1.6 times as much (docs/performance.md, "The viewer in
a browser"). A GPU does it at no noticeable cost, so a user's own browser keeps it."""

from __future__ import annotations

from typing import Any, Final

__all__ = ["CHROMIUM_ARGS", "launch_chromium"]

CHROMIUM_ARGS: Final = (
    "--no-sandbox",
    "--disable-gpu",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--webgl-antialiasing-mode=none",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
)


def launch_chromium(playwright: Any, executable: str | None) -> Any:
    """The Chromium at ``executable``, headless, launched through Playwright's sync API
    (``playwright`` as ``sync_playwright()`` enters it); Playwright is a test dependency, so
    it is passed in rather than imported here."""
    return playwright.chromium.launch(
        executable_path=executable, headless=True, args=list(CHROMIUM_ARGS)
    )
