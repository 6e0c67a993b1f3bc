"""The graph's errors: misuse, a service that failed, a service nobody offers."""

from __future__ import annotations

from belvedere.errors import BelvedereError

__all__ = ["GraphError", "ServiceFailedError", "ServiceUnavailableError"]


class GraphError(BelvedereError):
    """A misuse of the graph: type mismatch, missing service, time-out…"""


class ServiceFailedError(GraphError):
    """A service's handler failed: ``reason`` is what its server said."""

    def __init__(self, name: str, reason: str) -> None:
        super().__init__(f"service {name} failed: {reason}")
        self.service = name
        self.reason = reason


class ServiceUnavailableError(GraphError):
    """No node offers the service called."""
