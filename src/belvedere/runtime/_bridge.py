"""The Foxglove bridge beside a graph (``display``, ``sim``, ``launch``, ``run`` and
``foxglove`` start it the same way)."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from belvedere.foxglove import FoxgloveBridge
    from belvedere.graph import Graph

__all__ = ["BridgeOptions", "start_bridge"]


@dataclass(frozen=True)
class BridgeOptions:
    """Where the bridge serves, and whom."""

    port: int
    """A TCP port; 0: any free one."""
    host: str = "127.0.0.1"
    """The address it listens on (another than this machine's needs the URL's token)."""
    allow_origins: tuple[str, ...] = ()
    """Web origins besides this machine's pages and Foxglove's app that may connect."""


def start_bridge(
    graph: Graph, options: BridgeOptions | None, *, node_name: str = "foxglove_bridge"
) -> FoxgloveBridge | None:
    """The bridge ``options`` ask for on ``graph`` (None without options), its URL said on
    stderr; ``node_name``: its node on the graph."""
    if options is None:
        return None
    from belvedere.access import is_loopback
    from belvedere.foxglove import FoxgloveBridge

    bridge = FoxgloveBridge(
        graph,
        host=options.host,
        port=options.port,
        node_name=node_name,
        allow_origins=options.allow_origins,
    )
    if not is_loopback(bridge.host):
        sys.stderr.write(
            f"foxglove: serving beyond this machine on {bridge.host}: "
            "clients need the token in this URL\n"
        )
    sys.stderr.write(f"foxglove: {bridge.url}\n")
    return bridge
