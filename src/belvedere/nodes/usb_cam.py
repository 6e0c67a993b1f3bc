"""usb_cam's ``usb_cam_node``: a real camera (``~video_device``, /dev/video0) through
OpenCV's capture, publishing ``~image_raw``, ``~camera_info`` and ``~image_raw/compressed``
at ``~framerate``; without the device, one error naming it."""

from __future__ import annotations

import cv2

from belvedere.graph import Node
from belvedere.nodes._camera_info import read_calibration
from belvedere.nodes._registry import NodeSpec, Session, Starter, end_node, stopping_on_bad_values
from belvedere.nodes._video_source import Publishing, open_source, start_publishing
from belvedere.nodes.video_stream_opencv import _rate

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE"]

PACKAGE = "usb_cam"
_FOURCC = {"mjpeg": "MJPG", "yuyv": "YUYV", "uyvy": "UYVY"}


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    device = str(node.get_param("~video_device", "/dev/video0"))
    width = int(node.get_param("~image_width", 640))
    height = int(node.get_param("~image_height", 480))
    rate = _rate(node.get_param("~framerate", 30), "framerate")
    pixel_format = str(node.get_param("~pixel_format", "mjpeg"))
    if pixel_format not in (*_FOURCC, "mono8", "rgb24", "yuvmono10"):
        msg = f"parameter ~pixel_format: Unknown pixel format {pixel_format!r}"
        raise ValueError(msg)
    source = open_source(device, what="video device")
    capture = source.capture
    if capture is not None:  # what the device can: OpenCV keeps the nearest it offers
        capture.set(cv2.CAP_PROP_FRAME_WIDTH, width)
        capture.set(cv2.CAP_PROP_FRAME_HEIGHT, height)
        capture.set(cv2.CAP_PROP_FPS, rate)
        if pixel_format in _FOURCC:
            capture.set(cv2.CAP_PROP_FOURCC, cv2.VideoWriter.fourcc(*_FOURCC[pixel_format]))
    url = str(node.get_param("~camera_info_url", ""))
    how = Publishing(
        image_topic="~image_raw",
        info_topic="~camera_info",
        frame_id=str(node.get_param("~camera_frame_id", "head_camera")),
        rate=rate,
        loop=False,
        calibration=read_calibration(url, session.packages) if url else None,
    )
    start_publishing(node, source, how, lambda: end_node(session, node, 1))


EXECUTABLES: dict[str, Starter] = {"usb_cam_node": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
"""A client of the graph: ``run`` starts it on the graph that runs."""
