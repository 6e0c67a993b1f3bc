"""Debian's Chromium as the browser tests and the viewer's frame-rate benchmark run it:
headless, WebGL in software (SwiftShader: no GPU on a CI runner), nothing fetched in the
background. One command line, so the frame rate the benchmark measures is that of the
browser the tests check.

``antialias=False`` draws WebGL with one sample a pixel, as rviz's ``--disable-anti-aliasing``
is meant for software rendering: SwiftShader resolves Chromium's default 4 samples a pixel on
the CPU, and without them the viewer's frame under load cost 1.26-1.35 times less
(docs/performance.md, "The viewer in a browser"). A GPU multisamples at no noticeable cost,
so a user's own browser keeps it. The tests keep Chromium's default for now: with the faster
frames, test_browser_robots.py's multi-robot scene failed 4 runs in 6 (robot_3 drove where
robot_2 was commanded: a timing race outside the browser, not yet found)."""

from __future__ import annotations

from typing import Any, Final

__all__ = ["CHROMIUM_ARGS", "NO_MULTISAMPLING", "launch_chromium"]

CHROMIUM_ARGS: Final = (
    "--no-sandbox",
    "--disable-gpu",
    "--enable-unsafe-swiftshader",
    "--use-angle=swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
)
NO_MULTISAMPLING: Final = "--webgl-antialiasing-mode=none"
"""WebGL with one sample a pixel (a page's ``antialias: true`` is then ignored)."""


def launch_chromium(playwright: Any, executable: str | None, *, antialias: bool = True) -> Any:
    """The Chromium at ``executable``, headless, launched through Playwright's sync API
    (``playwright`` as ``sync_playwright()`` enters it); Playwright is a test dependency, so
    it is passed in rather than imported here. ``antialias``: WebGL's multisampling as a
    browser's default (4 samples a pixel) or none."""
    args = [*CHROMIUM_ARGS, *(() if antialias else (NO_MULTISAMPLING,))]
    return playwright.chromium.launch(executable_path=executable, headless=True, args=args)
