"""A pseudo-terminal for tests of what a user sees on a terminal (progress bars, a teleop's
keys): the program's side is ``slave`` (give it as stdin/stdout/stderr), the user's side is read
as it comes (a full terminal would block the program) and typed into."""

from __future__ import annotations

import os
import pty
import threading
from collections.abc import Callable

from tests.waiting import wait_until

__all__ = ["Terminal"]


class Terminal:
    def __init__(self) -> None:
        self.fd, self.slave = pty.openpty()
        self.output = b""
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        while True:
            try:
                chunk = os.read(self.fd, 4096)
            except OSError:
                return
            if not chunk:
                return
            self.output += chunk

    def wait_for(self, text: str) -> None:
        wait_until(
            lambda: text.encode() in self.output,
            what=f"the terminal to show {text!r}",
            detail=lambda: self.output[-200:],
        )

    def type(self, keys: str) -> None:
        os.write(self.fd, keys.encode())

    def press_until(self, key: str, done: Callable[[], bool], what: str) -> None:
        """Press ``key`` every 0.1 s (a teleop stops when no key comes) until ``done()``."""

        def press() -> bool:
            self.type(key)
            return done()

        wait_until(press, what=what, interval=0.1)

    def close(self) -> None:
        os.close(self.slave)
        os.close(self.fd)
