"""What the rqt nodes share: a browser page of their own, on the port their ``~port``
parameter names, its URL printed as a viewer's is."""

from __future__ import annotations

import shlex
import sys

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec
from belvedere.viewer import ToolPage

__all__ = ["open_page", "words"]


def words(spec: NodeSpec) -> list[str]:
    """The node's arguments, without the remaps and ``_param:=`` rosrun passes along."""
    return [w for w in shlex.split(spec.args) if ":=" not in w]


def open_page(spec: NodeSpec, node: Node, default_port: int) -> ToolPage:
    """The page of the node ``spec`` starts, its URL printed on stderr.

    Raises:
        ValueError: a ``~port`` that is no port number.
    """
    port = node.get_param("~port", default_port)
    if isinstance(port, bool) or not isinstance(port, int) or not 0 < port <= 65535:
        msg = f"parameter ~port: expected a port number (1 to 65535), got {port!r}"
        raise ValueError(msg)
    host = str(node.get_param("~address", "127.0.0.1"))
    page = ToolPage(spec.type, host=host, port=port)
    sys.stderr.write(f"{spec.type}: {page.url}\n")
    return page
