"""rqt_reconfigure's page in Debian's Chromium, as the course uses it: dynamic_tutorials'
``server.py`` and ``belvedere run rqt_reconfigure rqt_reconfigure`` as processes of their own
on this test's graph; a slider moved in the page reaches the server's callback, and a change
made by ``dynparam`` shows up in the page."""

from __future__ import annotations

import contextlib
import re
import subprocess
from collections.abc import Iterator
from typing import Any

import pytest

from tests.ros1.test_dynrec_scripts import RUN, Lines, dynparam, running
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.test_browser import browser_page
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.browser


@contextlib.contextmanager
def rqt_reconfigure(*args: str) -> Iterator[str]:
    """``belvedere run rqt_reconfigure rqt_reconfigure ARGS``; the URL it prints."""
    process = subprocess.Popen(
        [*RUN, "rqt_reconfigure", "rqt_reconfigure", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    assert process.stdout is not None
    out = Lines(process.stdout)
    try:
        line = wait_until(
            lambda: next((s for s in out.lines if s.startswith("rqt_reconfigure: ")), None),
            what="rqt_reconfigure to print its URL",
            detail=lambda: out.lines,
        )
        url = str(line).split(": ", 1)[1]
        assert re.fullmatch(r"http://127\.0\.0\.1:\d+", url), url
        yield url
    finally:
        process.terminate()
        process.wait(DEADLINE)


def _field(page: Any, label: str) -> Any:
    """The input right after the label ``label`` (a slider's number field follows it)."""
    return page.locator(f"xpath=//label[normalize-space()='{label}']/following::input[1]")


def test_the_page_reconfigures_the_tutorial_server(endpoint: str) -> None:
    del endpoint  # both processes join this test's own graph
    with running("server.py") as server, rqt_reconfigure() as url:
        wait_until(server.requests, what="the server's first callback", detail=lambda: server.lines)
        with browser_page(url) as page:
            # the tree lists the server; ticking it opens its parameters
            page.get_by_role("checkbox", name="dynamic_tutorials").check()
            for name in ("int_param", "double_param", "str_param", "bool_param", "size"):
                page.get_by_text(name, exact=True).wait_for()
            assert page.get_by_role("slider").count() == 2  # int_param's and double_param's

            # the int slider to its end: the server's callback gets its maximum
            thumb = page.get_by_role("slider").first
            assert thumb.get_attribute("aria-valuemax") == "100"
            thumb.focus()
            thumb.press("End")
            wait_until(
                lambda: any(r.startswith("100,") for r in server.requests()),
                what="the callback to get int_param = 100",
                detail=lambda: server.requests()[-3:],
            )

            # dynparam, another client, changes a value: the page shows it
            dynparam("set", "/dynamic_tutorials", "{double_param: 0.25, str_param: from dynparam}")
            wait_until(
                lambda: _field(page, "str_param").input_value() == "from dynparam",
                what="the page to show dynparam's str_param",
            )
            page.get_by_text("set int_param = 100").wait_for()
            page.mouse.move(700, 400)  # away from the tree's tooltips
            docs_screenshot(page, "rqt_reconfigure")
