"""Progress bars (rich) for long work on a terminal; nothing when the output is piped."""

from __future__ import annotations

import sys
from types import TracebackType

__all__ = ["ProgressBar", "wants_progress"]


def wants_progress(quiet: bool) -> bool:
    """Show progress: not asked to be quiet, and stderr is a terminal."""
    return not quiet and sys.stderr.isatty()


class ProgressBar:
    """One bar: ``label``, done/total seconds, and a line of status text (safe from any
    thread). Disabled, it does nothing."""

    def __init__(self, label: str, total: float, *, enabled: bool) -> None:
        self.enabled = enabled
        self._progress = None
        self._task = None
        if not enabled:
            return
        from rich.console import Console
        from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn

        self._progress = Progress(
            TextColumn("{task.description}"),
            BarColumn(),
            TaskProgressColumn(),
            TextColumn("{task.fields[status]}"),
            console=Console(stderr=True),
            refresh_per_second=8,
        )
        self._task = self._progress.add_task(label, total=max(total, 1e-9), status="")
        self._progress.start()

    def update(self, done: float, status: str = "", label: str | None = None) -> None:
        if self._progress is None or self._task is None:
            return
        if label is None:
            self._progress.update(self._task, completed=done, status=status)
        else:
            self._progress.update(self._task, completed=done, status=status, description=label)

    def close(self) -> None:
        if self._progress is not None:
            self._progress.stop()
            self._progress = None

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()
