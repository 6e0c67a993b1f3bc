"""rqt_image_view in the browser: the newest frame of an image topic (``sensor_msgs/Image``
or ``CompressedImage``), picked from the graph's image topics.

The subscription keeps one frame (queue size 1, as image_transport's display does); a thread
of the page's own converts and JPEG-encodes the newest whenever one has arrived, so the page
runs at the camera's rate when it can and skips frames, never falls behind, when it cannot.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Final

import numpy as np

from belvedere.errors import BelvedereError
from belvedere.graph import GraphTopics, Node
from belvedere.msgs import compressed_rgb, image_rgb, short
from belvedere.viewer._tool_page import ToolPage

__all__ = ["IMAGE_TYPES", "ImagePage"]

IMAGE_TYPES: Final = ("sensor_msgs/Image", "sensor_msgs/CompressedImage")
JPEG_QUALITY: Final = 80
NONE: Final = "(no image topic)"


class ImagePage:
    """Shows ``topic`` (or the first image topic the graph publishes) on ``page``."""

    def __init__(self, node: Node, page: ToolPage, topic: str | None = None) -> None:
        self.node = node
        self.page = page
        self.topics = GraphTopics(node.graph)
        self.topic: str | None = None
        self.sent = 0
        """Frames handed to the page."""
        self.received = 0
        self._subscription: Any = None
        self._newest: Any = None
        self._arrived = threading.Condition()
        self._stop = threading.Event()
        self._rate = (time.monotonic(), 0)
        self.fps = 0.0
        self.shape: tuple[int, int, str] | None = None
        """The last frame's width, height and encoding (or compressed format)."""
        gui = page.gui
        self.picker = gui.add_dropdown("Topic", [topic or NONE], initial_value=topic or NONE)
        self.picker.on_update(lambda _: self.show(self.picker.value))
        self.status = gui.add_markdown("waiting for an image topic")
        blank = np.zeros((480, 640, 3), dtype=np.uint8)
        self.image = gui.add_image(blank, format="jpeg", jpeg_quality=JPEG_QUALITY)
        self._wanted = topic
        node.timer(1.0, self._list_topics)
        self._thread = threading.Thread(target=self._send, name="belvedere-rqt-image", daemon=True)
        self._thread.start()
        page.start(self._report)

    def image_topics(self) -> list[str]:
        wanted = {short(t) for t in IMAGE_TYPES}
        return sorted(n for n, t in self.topics.published().items() if short(t) in wanted)

    def _list_topics(self) -> None:
        found = self.image_topics()
        if self.topic is not None and self.topic not in found:
            found.append(self.topic)
        if found and list(self.picker.options) != found:
            self.picker.options = found
        wanted = self._wanted or (found[0] if found else None)
        if self.topic is None and wanted in found:
            self.show(wanted)

    def show(self, topic: str) -> None:
        """Subscribe to ``topic`` in place of the one shown."""
        if topic == self.topic or topic == NONE:
            return
        msg_type = self.topics.type_of(topic)
        if msg_type is None or short(msg_type) not in {short(t) for t in IMAGE_TYPES}:
            self.status.content = f"{topic}: not an image topic ({msg_type or 'not published'})"
            return
        if self._subscription is not None:
            self._subscription.unregister()
        self.topic, self._wanted = topic, topic
        self.picker.value = topic
        self._subscription = self.node.subscribe(topic, msg_type, self._take, queue_size=1)

    def _take(self, msg: Any) -> None:
        with self._arrived:
            self.received += 1
            self._newest = msg
            self._arrived.notify()

    def _send(self) -> None:
        while not self._stop.is_set():
            with self._arrived:
                self._arrived.wait_for(lambda: self._newest is not None or self._stop.is_set())
                msg, self._newest = self._newest, None
            if msg is None:
                continue
            try:
                rgb = compressed_rgb(msg) if hasattr(msg, "format") else image_rgb(msg)
            except BelvedereError as err:
                self.status.content = f"{self.topic}: {err.message}"
                continue
            self.image.image = rgb
            self.sent += 1
            kind = str(getattr(msg, "encoding", None) or getattr(msg, "format", "?"))
            self.shape = (rgb.shape[1], rgb.shape[0], kind)

    def _report(self) -> None:
        now = time.monotonic()
        last, count = self._rate
        if now - last >= 1.0:
            self.fps = (self.sent - count) / (now - last)
            self._rate = (now, self.sent)
            shape = self.shape
            if shape is not None and self.topic is not None:
                width, height, encoding = shape
                self.status.content = (
                    f"{self.topic}: {width} x {height} {encoding}, {self.fps:.1f} frames/s sent"
                )

    def close(self) -> None:
        self._stop.set()
        with self._arrived:
            self._arrived.notify()
        self._thread.join(timeout=2)
        self.page.close()
        self.topics.close()
