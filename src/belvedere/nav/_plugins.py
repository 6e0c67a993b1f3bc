"""What the navigation plugin factories share: the error for a name they do not know."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["UnknownPluginError"]


class UnknownPluginError(ValueError):
    """A planner plugin name that is not one of those supported (pluginlib's "failed to create")."""

    def __init__(self, kind: str, name: str, supported: Iterable[str]) -> None:
        self.name = name
        self.supported = tuple(supported)
        text = f"unknown {kind} plugin {name!r} (supported: {', '.join(self.supported)})"
        super().__init__(text)
