"""foxglove_bridge: the graph's topics served to Foxglove, as ROS 1's foxglove_bridge node.

Its parameters ``port`` (8765), ``address`` and ``topic_whitelist`` apply. ``address``
defaults to the loopback interface here (ROS's node listens on every interface): give
``0.0.0.0`` to serve other machines, whose clients then need the run's token (the URL with
it is logged as a warning). Web pages of this machine and Foxglove's web app may connect,
and clients that are no web page. The bridge's other parameters (TLS, compression, service
and parameter whitelists …) are not applied; one warning names those that are set.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

from belvedere.graph import Node
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    StartError,
    port_param,
    stopping_on_bad_values,
)

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "foxglove_bridge"

logger = logging.getLogger("belvedere.launch")

NOT_APPLIED = (
    "tls",
    "certfile",
    "keyfile",
    "send_buffer_limit",
    "use_compression",
    "capabilities",
    "param_whitelist",
    "service_whitelist",
    "client_topic_whitelist",
    "max_update_ms",
    "asset_uri_allowlist",
    "num_threads",
)
"""foxglove_bridge's parameters this bridge reads past (it serves every capability it has)."""


def _patterns(node: Node) -> Sequence[str]:
    patterns = node.get_param("~topic_whitelist", [".*"])
    if isinstance(patterns, str):
        patterns = [patterns]
    if not isinstance(patterns, list) or not all(isinstance(p, str) for p in patterns):
        msg = (
            f"parameter ~topic_whitelist: expected a list of regular expressions, got {patterns!r}"
        )
        raise ValueError(msg)
    return patterns


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    from belvedere.foxglove import FoxgloveBridge, FoxgloveBridgeError

    host = str(node.get_param("~address", "127.0.0.1"))
    ignored = [name for name in NOT_APPLIED if node.get_param(f"~{name}", None) is not None]
    if ignored:
        logger.warning(
            "%s: foxglove_bridge parameters not applied here: %s",
            spec.full_name,
            ", ".join(ignored),
        )
    try:
        bridge = FoxgloveBridge(
            session.graph,
            host=host,
            port=port_param(node, 8765),
            node=node,
            topic_whitelist=_patterns(node),
        )
    except FoxgloveBridgeError as err:
        msg = f"{spec.full_name}: {err.message}"
        raise StartError(msg, spec.source, hint=err.hint) from None
    session.closers.append(bridge.close)
    if bridge.access.token is None:
        logger.info("%s: Foxglove can connect to %s", spec.full_name, bridge.url)
    else:
        logger.warning(
            "%s: serving beyond this machine on %s: Foxglove clients need the token in %s",
            spec.full_name,
            host,
            bridge.url,
        )


EXECUTABLES: dict[str, Starter] = {"foxglove_bridge": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs, as rosrun joins the master."""
