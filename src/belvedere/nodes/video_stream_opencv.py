"""video_stream_opencv's ``video_stream``: a video file, a folder of pictures or a device
(``~video_stream_provider``) as a camera publishing ``image_raw``, ``camera_info`` and
``image_raw/compressed`` in its namespace, at ``~fps`` (else the video's own rate; never
above ``~set_camera_fps``, as video_stream_opencv caps it), one frame a tick: frames
``~start_frame`` … ``~stop_frame`` - 1 of a video, looping back to ``~start_frame`` with
``~loop_videofile``. ``~buffer_queue_size`` is not needed: frames are read as they are
published, in graph time, so none wait in a queue."""

from __future__ import annotations

import cv2

from belvedere.graph import Node
from belvedere.nodes._camera_info import read_calibration
from belvedere.nodes._registry import NodeSpec, Session, Starter, end_node, stopping_on_bad_values
from belvedere.nodes._video_source import Publishing, open_source, start_publishing

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "video_stream_opencv"


def _flag(node: Node, name: str) -> bool:
    value = node.get_param(f"~{name}", False)
    if not isinstance(value, bool):
        msg = f"parameter ~{name}: expected true or false, got {value!r}"
        raise ValueError(msg)
    return value


def _rate(value: object, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or value <= 0:
        msg = f"parameter ~{name}: expected a positive number of frames per second, got {value!r}"
        raise ValueError(msg)
    return float(value)


def _frame_number(node: Node, name: str, default: int, low: int) -> int:
    value = node.get_param(f"~{name}", default)
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        msg = f"parameter ~{name}: expected a whole number of at least {low}, got {value!r}"
        raise ValueError(msg)
    return value


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    provider = node.get_param("~video_stream_provider", 0)
    source = open_source(provider, what="~video_stream_provider")
    fps = node.get_param("~fps", None)
    rate = _rate(fps, "fps") if fps is not None else (source.rate or 30.0)
    camera_fps = node.get_param("~set_camera_fps", None)
    if camera_fps is not None:
        camera_fps = _rate(camera_fps, "set_camera_fps")
        if rate > camera_fps:
            node.logger.warning(
                "Asked to publish at 'fps' (%g) which is higher than the 'set_camera_fps' "
                "(%g), we can't publish faster than the camera provides images.",
                rate,
                camera_fps,
            )
            rate = camera_fps
        if source.capture is not None and source.frame_count is None:
            source.capture.set(cv2.CAP_PROP_FPS, camera_fps)  # a device: ask it for that rate
    start = _frame_number(node, "start_frame", 0, 0)
    stop = _frame_number(node, "stop_frame", -1, -1)
    for warning in source.play_range(start, stop):
        node.logger.error("%s", warning)
    url = str(node.get_param("~camera_info_url", ""))
    width, height = node.get_param("~width", 0), node.get_param("~height", 0)
    how = Publishing(
        image_topic="image_raw",
        info_topic="camera_info",
        frame_id=str(node.get_param("~frame_id", "camera")),
        rate=rate,
        loop=_flag(node, "loop_videofile"),
        flip_horizontal=_flag(node, "flip_horizontal"),
        flip_vertical=_flag(node, "flip_vertical"),
        calibration=read_calibration(url, session.packages) if url else None,
        size=(int(width), int(height)) if width and height else None,
    )
    start_publishing(node, source, how, lambda: end_node(session, node))


EXECUTABLES: dict[str, Starter] = {"video_stream": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs."""
