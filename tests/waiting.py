"""Waiting on a condition instead of on the clock.

A test that sleeps and then asserts races whatever it waits for (a renderer, a browser, another
process) and fails on a busy machine. Tests wait for the condition itself, with a deadline far
beyond what a loaded single core needs, so only a condition that never comes fails, and it
fails saying what it waited for.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

__all__ = ["DEADLINE", "wait_until"]

T = TypeVar("T")

DEADLINE = 60.0
"""Seconds: generous for one busy core shared with a browser and other processes."""


def wait_until(
    predicate: Callable[[], T],
    *,
    what: str,
    timeout: float = DEADLINE,
    interval: float = 0.02,
    detail: Callable[[], object] | None = None,
) -> T:
    """The first truthy value of ``predicate()``, polled every ``interval`` seconds.

    Fails with an AssertionError naming ``what`` (and ``detail()``, e.g. the last value seen)
    if none comes within ``timeout`` seconds.
    """
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            msg = f"waited {timeout:g} s for {what}"
            if detail is not None:
                msg += f"; last seen: {detail()}"
            raise AssertionError(msg)
        time.sleep(interval)
