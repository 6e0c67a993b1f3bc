"""Reading single keys from a real terminal, and the teleop loop around a layout.

The terminal is put in raw mode (keys arrive one by one, Ctrl-C arrives as a key) and is
restored on the way out whatever happens; the robot is sent a zero Twist on the way out too.
"""

from __future__ import annotations

import contextlib
import os
import select
import termios
import tty
from collections.abc import Callable, Iterator
from typing import TextIO

from belvedere.errors import BelvedereError
from belvedere.teleop._layouts import Layout

__all__ = ["raw_terminal", "read_key", "run_teleop"]

Twist = tuple[float, float, float, float]


@contextlib.contextmanager
def raw_terminal(fd: int) -> Iterator[None]:
    """Raw mode on ``fd`` for the duration of the block; the settings are always restored."""
    if not os.isatty(fd):
        msg = "teleop reads keys from a terminal, but its input is not one"
        raise BelvedereError(msg, hint="run it in a terminal window of its own")
    saved = termios.tcgetattr(fd)
    try:
        tty.setraw(fd)
        yield
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)


def read_key(fd: int, timeout: float | None) -> str | None:
    """One key, None when ``timeout`` passes first, ``"\\x03"`` (Ctrl-C) at end of input."""
    ready, _, _ = select.select([fd], [], [], timeout)
    if not ready:
        return None
    data = os.read(fd, 1)
    if not data:
        return "\x03"
    return data.decode("utf-8", errors="replace")


def run_teleop(layout: Layout, publish: Callable[[Twist], None], fd: int, out: TextIO) -> None:
    """Read keys until Ctrl-C, publishing what the layout says; finish with a zero Twist."""

    def say(text: str) -> None:
        # raw mode: a newline does not return the carriage by itself
        out.write(text.replace("\r\n", "\n").replace("\n", "\r\n") + "\r\n")
        out.flush()

    with raw_terminal(fd):
        say(layout.help)
        try:
            while True:
                key = read_key(fd, layout.poll)
                output = layout.idle() if key is None else layout.key(key)
                if output.text:
                    say(output.text)
                if output.quit:
                    break
                if output.twist is not None:
                    publish(output.twist)
        finally:
            publish((0.0, 0.0, 0.0, 0.0))
