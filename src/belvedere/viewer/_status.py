"""Statuses as rviz shows them: named entries (Topic, Transform, …), each Ok, Warn or Error
with a text; the worst level is the display's."""

from __future__ import annotations

import threading
from enum import IntEnum

__all__ = ["Level", "Status"]


class Level(IntEnum):
    OK = 0
    WARN = 1
    ERROR = 2

    @property
    def label(self) -> str:
        return ("Ok", "Warn", "Error")[self]


class Status:
    """A display's (or the global) status entries, written from any thread."""

    def __init__(self) -> None:
        self._entries: dict[str, tuple[Level, str]] = {}
        self._lock = threading.Lock()
        self.version = 0
        """Counts changes, so a panel redraws only when something changed."""

    def set(self, name: str, level: Level, text: str) -> None:
        with self._lock:
            if self._entries.get(name) != (level, text):
                self._entries[name] = (level, text)
                self.version += 1

    def clear(self, name: str) -> None:
        with self._lock:
            if self._entries.pop(name, None) is not None:
                self.version += 1

    def get(self, name: str) -> tuple[Level, str] | None:
        with self._lock:
            return self._entries.get(name)

    def entries(self) -> list[tuple[str, Level, str]]:
        with self._lock:
            return [(name, level, text) for name, (level, text) in self._entries.items()]

    @property
    def level(self) -> Level:
        with self._lock:
            return max((level for level, _ in self._entries.values()), default=Level.OK)

    def markdown(self) -> str:
        """The entries as the panel shows them (rviz's Status subtree)."""
        lines = [f"**Status: {self.level.label}**"]
        lines += [f"- {level.label} · {name}: {text}" for name, level, text in self.entries()]
        return "\n".join(lines)
