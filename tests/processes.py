"""``python -m belvedere …`` in a process of its own, as a user starts it, for tests that
need one beside their graph: started, then waited for until it says on stderr that it is
ready."""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

from tests.waiting import DEADLINE

__all__ = ["BelvedereProcess"]


class BelvedereProcess:
    """``belvedere *args``, once a line of its stderr starts with ``ready`` (that line is
    :attr:`ready`; every line read is in :attr:`lines`, for the failure that follows).

    Raises:
        AssertionError: it ended first, saying ``ended`` and what it printed.
    """

    def __init__(
        self,
        args: list[str],
        *,
        ready: str,
        ended: str,
        cwd: Path | None = None,
        stdout: int | None = None,
    ) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "belvedere", *args],
            cwd=cwd,
            stdout=stdout,
            stderr=subprocess.PIPE,
            text=True,
        )
        self.lines: list[str] = []
        assert self.proc.stderr is not None
        while True:
            line = self.proc.stderr.readline()
            assert line, f"{ended}: {''.join(self.lines)}"
            self.lines.append(line)
            if line.startswith(ready):
                self.ready = line
                break

    def stop(self, sig: int = signal.SIGINT) -> str:
        """Send ``sig`` (unless it ended already) and wait: all it printed on stderr."""
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        _, err = self.proc.communicate(timeout=DEADLINE)
        return "".join(self.lines) + err
