"""The Chromium the browser tests and benchmarks launch (:mod:`belvedere.viewer._chromium`)."""

from __future__ import annotations

import shutil

import pytest

from belvedere.viewer._chromium import launch_chromium

pytestmark = pytest.mark.browser


def test_software_rendering_can_draw_without_multisampling() -> None:
    """``launch_chromium(antialias=False)`` (benchmarks/viewer.py's default) gives a page's
    WebGL one sample a pixel though the page asks for antialiasing, as viser's canvas does;
    by default, Chromium's 4. Software WebGL resolves those samples on the CPU."""
    if shutil.which("chromium") is None:
        pytest.skip("Debian's chromium is not installed")
    playwright = pytest.importorskip("playwright.sync_api")
    ask = """() => {
        const gl = document.createElement("canvas").getContext("webgl2", {antialias: true});
        return [gl.getContextAttributes().antialias, gl.getParameter(gl.SAMPLES)];
    }"""
    seen = {}
    with playwright.sync_playwright() as p:
        for antialias in (True, False):
            browser = launch_chromium(p, shutil.which("chromium"), antialias=antialias)
            try:
                seen[antialias] = browser.new_page().evaluate(ask)
            finally:
                browser.close()
    assert seen == {True: [True, 4], False: [False, 0]}
