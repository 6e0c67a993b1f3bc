"""What move_base's plugin parameters (``base_global_planner``, ``base_local_planner``) may name."""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["UnknownPluginError"]


class UnknownPluginError(ValueError):
    """A planner plugin name belvedere does not provide (move_base's pluginlib lookup fails)."""

    def __init__(self, kind: str, name: str, supported: Iterable[str]) -> None:
        self.kind = kind
        """``"global planner"`` or ``"local planner"``."""
        self.name = name
        self.supported = tuple(supported)
        names = ", ".join(self.supported)
        super().__init__(f"unknown {kind} plugin {name!r} (supported: {names})")
