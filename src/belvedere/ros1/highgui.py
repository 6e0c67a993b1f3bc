"""OpenCV's windows (``cv2.imshow``, ``namedWindow``, ``waitKey``, ``destroyWindow``,
``destroyAllWindows``) for the scripts belvedere runs, where there is no screen.

The headless OpenCV wheel belvedere depends on has no GUI, and a script belvedere runs has
no display in the normal case; so each named window becomes an image topic,
``/image_window/<name>`` (sensor_msgs/Image, bgr8/mono8/bgra8 as shown), once the script's
node is initialized, with the window's name as the script spelled it on
``/image_window/<name>/name`` (std_msgs/String, latched). The viewer shows every such topic
on the graph as a panel of its own, titled with the window's name, and takes it away when
the window is destroyed (its publisher gone); rqt_image_view's page shows one too.

Keys come back on ``/image_window/<name>/key`` (std_msgs/Int32, OpenCV's key code: the
character's code for a printable key, 13 Enter, 27 Escape, 8 Backspace, 9 Tab), which the
viewer publishes for the keys typed into the window's panel. ``waitKey(delay)`` returns the
next key of any window, waiting up to ``delay`` ms (wall time, as OpenCV) or, for a delay of
0 or less, until a key comes; it returns -1 when the time is up, when the script has no
window (nothing could send a key) and when rospy shuts down. Moving, sizing and titling a
window do nothing (the browser places its panels, titled with the window's name). When the
OpenCV a user installed has its own GUI and a DISPLAY is set, its windows are left alone.
"""

from __future__ import annotations

import os
import queue
import re
import sys
import time
from dataclasses import dataclass
from types import ModuleType
from typing import Any, Final

import numpy as np

__all__ = [
    "KEY_SUFFIX",
    "KEY_TYPE",
    "NAME_SUFFIX",
    "NAME_TYPE",
    "TOPIC_PREFIX",
    "has_own_gui",
    "install",
    "key_topic_of",
    "topic_of",
]

TOPIC_PREFIX: Final = "/image_window"
KEY_SUFFIX: Final = "/key"
"""A window's keys are on its image topic with this suffix (std_msgs/Int32)."""
KEY_TYPE: Final = "std_msgs/Int32"
NAME_SUFFIX: Final = "/name"
"""A window's name, as the script spelled it, is on its image topic with this suffix
(std_msgs/String, latched): the topic's name has only letters, digits and ``_``."""
NAME_TYPE: Final = "std_msgs/String"
_POLL_S: Final = 0.05
"""How often a waiting ``waitKey`` looks whether rospy is shutting down."""
_windows: dict[str, _Window] = {}
_keys: queue.SimpleQueue[int] = queue.SimpleQueue()
"""Keys typed into any window, oldest first (OpenCV's waitKey reads one queue too)."""
_noticed: set[str] = set()


def topic_of(window: str) -> str:
    """The image topic a window's pictures are published on."""
    name = re.sub(r"[^A-Za-z0-9_]+", "_", window).strip("_") or "window"
    if not name[0].isalpha():
        name = f"w_{name}"
    return f"{TOPIC_PREFIX}/{name}"


def key_topic_of(window: str) -> str:
    """The topic the keys typed into a window come on."""
    return topic_of(window) + KEY_SUFFIX


def has_own_gui(cv2: ModuleType) -> bool:
    """Whether this OpenCV was built with a GUI backend (the headless wheel is not)."""
    info = cv2.getBuildInformation()
    gui = re.search(r"GUI:\s*(\S+)", info)
    return gui is not None and gui[1].upper() not in ("NONE", "NO")


def _shown(image: Any) -> tuple[Any, str]:
    """The picture imshow shows for ``image`` (OpenCV scales 16-bit by 1/256 and floats by
    255) and its encoding."""
    array = np.asarray(image)
    if array.dtype == np.uint16:
        array = (array >> 8).astype(np.uint8)
    elif array.dtype.kind == "f":
        array = np.clip(np.rint(array * 255.0), 0, 255).astype(np.uint8)
    elif array.dtype != np.uint8:
        array = np.clip(array, 0, 255).astype(np.uint8)
    if array.ndim == 3 and array.shape[2] == 1:
        array = array[:, :, 0]
    encoding = "mono8" if array.ndim == 2 else "bgra8" if array.shape[2] == 4 else "bgr8"
    return np.ascontiguousarray(array), encoding


@dataclass(frozen=True)
class _Window:
    """A window's topics: its pictures and name out, its keys in."""

    pictures: Any
    name: Any
    keys: Any

    def close(self) -> None:
        for endpoint in (self.pictures, self.name, self.keys):
            endpoint.unregister()


def _open(winname: str) -> _Window:
    from belvedere.ros1 import message_class, rospy

    topic = topic_of(winname)
    window = _Window(
        pictures=rospy.Publisher(topic, message_class("sensor_msgs/Image"), queue_size=1),
        name=rospy.Publisher(
            topic + NAME_SUFFIX, message_class(NAME_TYPE), queue_size=1, latch=True
        ),
        keys=rospy.Subscriber(
            topic + KEY_SUFFIX, message_class(KEY_TYPE), _key_typed, queue_size=100
        ),
    )
    window.name.publish(window.name.data_class(data=winname))
    _windows[winname] = window
    sys.stderr.write(
        f"[belvedere] cv2 window {winname!r} is the image topic {topic}: the viewer "
        f"shows it (or belvedere run rqt_image_view rqt_image_view {topic}); keys typed "
        "in its panel reach cv2.waitKey\n"
    )
    return window


def imshow(winname: str, mat: Any) -> None:
    from belvedere.ros1.rospy import _state

    if not _state.is_initialized():
        if winname not in _noticed:
            _noticed.add(winname)
            sys.stderr.write(
                f"[belvedere] cv2.imshow({winname!r}): no window here; call "
                "rospy.init_node first to see it in the browser\n"
            )
        return
    window = _windows.get(winname) or _open(winname)
    from belvedere.ros1.cv_bridge import CvBridge

    array, encoding = _shown(mat)
    window.pictures.publish(CvBridge().cv2_to_imgmsg(array, encoding))


def named_window(winname: str, flags: int = 0) -> None:
    del flags  # sizes are the browser's


def place_window(winname: str, *args: Any) -> None:
    del winname, args  # placing and sizing are the browser's


def _key_typed(msg: Any) -> None:
    _keys.put(int(msg.data))


def wait_key(delay: float = 0) -> int:
    """OpenCV's waitKey: the next key typed into a window, or -1 after ``delay`` ms."""
    from belvedere.ros1.rospy import _state

    deadline = time.monotonic() + delay / 1000.0 if delay > 0 else None
    if deadline is None and not _windows and _keys.empty():
        return -1  # no window: no key can ever come, and a script must not hang here
    stopping = _state.shutdown_event()
    while True:
        left = _POLL_S if deadline is None else min(_POLL_S, deadline - time.monotonic())
        try:
            return _keys.get(timeout=max(0.0, left))
        except queue.Empty:
            pass
        if stopping.is_set() or (deadline is not None and time.monotonic() >= deadline):
            return -1


def destroy_window(winname: str) -> None:
    window = _windows.pop(winname, None)
    if window is not None:
        window.close()


def destroy_all_windows() -> None:
    for name in list(_windows):
        destroy_window(name)


def install(cv2: ModuleType) -> None:
    """Give ``cv2`` these windows, unless it has its own GUI and a display to show them."""
    if has_own_gui(cv2) and os.environ.get("DISPLAY"):
        return
    windows = {
        "imshow": imshow,
        "namedWindow": named_window,
        "waitKey": wait_key,
        "waitKeyEx": wait_key,
        "destroyWindow": destroy_window,
        "destroyAllWindows": destroy_all_windows,
        "moveWindow": place_window,
        "resizeWindow": place_window,
        "setWindowTitle": place_window,
    }
    for name, function in windows.items():
        setattr(cv2, name, function)
