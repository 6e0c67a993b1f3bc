"""What the picture tools (rqt_graph, rqt_tf_tree, view_frames) share: ``dot`` checked at the
node's start, a TF watch, and a page whose URL is printed."""

from __future__ import annotations

import sys

from belvedere.graph import Node
from belvedere.nodes._registry import NodeSpec, Session, StartError
from belvedere.pictures import DotError, Draw, FramesWatch, PicturePage, publishers_of, require_dot

__all__ = ["needs_dot", "serve_page", "watch_frames"]


def needs_dot(spec: NodeSpec) -> None:
    """A missing ``dot`` is the node's one error at its start (its launch line)."""
    try:
        require_dot()
    except DotError as err:
        msg = f"{spec.full_name}: {err.message}"
        raise StartError(msg, spec.source) from None


def watch_frames(session: Session, spec: NodeSpec, node: Node) -> FramesWatch:
    """A TF watch on ``node``, for as long as the session runs."""
    needs_dot(spec)
    watch = FramesWatch(node, lambda topic: publishers_of(session.graph, topic))
    session.closers.append(watch.close)
    return watch


def serve_page(
    session: Session, node: Node, title: str, draw: Draw, *, controls: str = ""
) -> PicturePage:
    """The page of ``draw``'s picture on 127.0.0.1 (``~port``, else a free one), its URL said
    on stderr as the viewer's is; closed with the session."""
    port = int(node.get_param("~port", 0))
    page = PicturePage(title, draw, controls=controls, port=port)
    session.closers.append(page.close)
    sys.stderr.write(f"{title}: {page.url}\n")
    sys.stderr.flush()
    return page
