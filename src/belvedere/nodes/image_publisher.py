"""image_publisher: a picture, a folder of pictures or a video file (its argument, or
``~filename``) published again and again on ``~image_raw`` with ``~camera_info`` and
``~image_raw/compressed`` at ``~publish_rate`` (10 Hz); a video starts over at its end."""

from __future__ import annotations

import shlex

from belvedere.graph import Node
from belvedere.nodes._camera_info import read_calibration
from belvedere.nodes._registry import NodeSpec, Session, Starter, stopping_on_bad_values
from belvedere.nodes._video_source import Publishing, open_source, start_publishing
from belvedere.nodes.video_stream_opencv import _flag, _rate

__all__ = ["ANONYMOUS", "EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "image_publisher"


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    args = [a for a in shlex.split(spec.args) if ":=" not in a]
    filename = args[0] if args else node.get_param("~filename", None)
    if not filename:
        msg = "expected a file to publish: image_publisher FILE (or the parameter ~filename)"
        raise ValueError(msg)
    source = open_source(str(filename), what="file")
    url = str(node.get_param("~camera_info_url", ""))
    how = Publishing(
        image_topic="~image_raw",
        info_topic="~camera_info",
        frame_id=str(node.get_param("~frame_id", "camera")),
        rate=_rate(node.get_param("~publish_rate", 10.0), "publish_rate"),
        loop=True,
        flip_horizontal=_flag(node, "flip_horizontal"),
        flip_vertical=_flag(node, "flip_vertical"),
        calibration=read_calibration(url, session.packages) if url else None,
    )
    start_publishing(node, source, how, lambda: None)


EXECUTABLES: dict[str, Starter] = {"image_publisher": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
ANONYMOUS = frozenset(EXECUTABLES)
"""``rosrun image_publisher image_publisher FILE`` is /image_publisher_<number>."""
