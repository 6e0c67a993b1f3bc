"""OpenCV's windows for the scripts belvedere runs, where there is no screen: each
``cv2.imshow`` window is published as a ``sensor_msgs/Image`` on ``/cv_windows/<name>``, to
be seen in the browser (``belvedere run rqt_image_view rqt_image_view /cv_windows/<name>``, or
the viewer's Image display), and ``cv2.waitKey`` waits its delay and returns -1 (no key:
never for ever, a script waiting for a key would hang).

Put in place by ``rospy.init_node`` when the script has imported ``cv2`` and OpenCV cannot
open a window here (no ``DISPLAY``, or the headless wheel)."""

from __future__ import annotations

import logging
import os
import re
import sys
import threading
import time
from typing import Any

import numpy as np

__all__ = ["TOPIC_PREFIX", "install", "window_topic"]

logger = logging.getLogger("belvedere.ros1")

TOPIC_PREFIX = "/cv_windows/"
_ENCODINGS = {1: "mono8", 3: "bgr8", 4: "bgra8"}


def window_topic(name: str) -> str:
    """``/cv_windows/<name>``, the name made a graph name (``Image window`` → ``Image_window``)."""
    cleaned = re.sub(r"[^A-Za-z0-9_]", "_", name).strip("_") or "window"
    if cleaned[0].isdigit():
        cleaned = "w" + cleaned
    return TOPIC_PREFIX + cleaned


def _has_screen(cv2: Any) -> bool:
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        return False
    info = cv2.getBuildInformation()
    return not re.search(r"GUI:\s+NONE", info)


class _Windows:
    def __init__(self, runtime: Any) -> None:
        self.runtime = runtime
        self.publishers: dict[str, Any] = {}
        self.lock = threading.Lock()
        self.said_wait = False

    def publisher(self, name: str) -> Any:
        with self.lock:
            pub = self.publishers.get(name)
            if pub is None:
                topic = window_topic(name)
                pub = self.runtime.run_on_executor(
                    lambda: self.runtime.node.publisher(topic, "sensor_msgs/Image", latch=True)
                )
                self.publishers[name] = pub
                logger.warning(
                    "cv2 window %r has no screen here: shown on %s (belvedere run "
                    "rqt_image_view rqt_image_view %s)",
                    name,
                    topic,
                    topic,
                )
            return pub

    def imshow(self, name: str, image: Any) -> None:
        array = np.asarray(image)
        if array.dtype != np.uint8:
            # OpenCV shows 16-bit images divided by 256 and float ones times 255
            scale = 1 / 256 if array.dtype == np.uint16 else 255.0
            array = np.clip(array.astype(np.float64) * scale, 0, 255).astype(np.uint8)
        channels = 1 if array.ndim == 2 else array.shape[2]
        encoding = _ENCODINGS.get(channels)
        if encoding is None:
            msg = f"cv2.imshow: an image of {channels} channels cannot be shown"
            raise ValueError(msg)
        array = np.ascontiguousarray(array)
        height, width = array.shape[:2]
        data = {
            "header": {"frame_id": name},
            "height": height,
            "width": width,
            "encoding": encoding,
            "step": width * channels,
            "data": array.tobytes(),
        }
        pub = self.publisher(name)
        self.runtime.graph.executor.post(lambda: pub.publish_data(data))

    def wait_key(self, delay: int = 0) -> int:
        if delay <= 0:
            if not self.said_wait:
                self.said_wait = True
                logger.warning("cv2.waitKey(0): no keyboard reaches a window here; returning -1")
            return -1
        time.sleep(delay / 1000.0)
        return -1


def install(runtime: Any) -> bool:
    """Replace cv2's window functions if the script imported cv2 and there is no screen;
    whether they were replaced."""
    cv2: Any = sys.modules.get("cv2")
    if cv2 is None or getattr(cv2, "_belvedere_windows", False) or _has_screen(cv2):
        return False
    windows = _Windows(runtime)
    cv2.imshow = windows.imshow
    cv2.waitKey = windows.wait_key
    cv2.waitKeyEx = windows.wait_key
    cv2.pollKey = lambda: -1
    cv2.namedWindow = lambda *args, **kwargs: None
    cv2.destroyWindow = lambda *args, **kwargs: None
    cv2.destroyAllWindows = lambda *args, **kwargs: None
    cv2.moveWindow = lambda *args, **kwargs: None
    cv2.resizeWindow = lambda *args, **kwargs: None
    cv2.startWindowThread = lambda *args, **kwargs: 0
    cv2._belvedere_windows = True
    return True
