"""OpenCV's windows of the graph's scripts, each a panel of the viewer.

A script's ``cv2.imshow(name, image)`` publishes ``/image_window/<name>``
(:mod:`belvedere.ros1.highgui`); the viewer shows every such topic it finds on the graph,
without being asked, in a panel titled with the window's name, and takes the panel away when
the topic has no publisher left (``cv2.destroyWindow``, or the script ended). Under the
picture, a key field sends what is typed into it back to the script's ``cv2.waitKey`` on
``/image_window/<name>/key`` (std_msgs/Int32, OpenCV's key codes), with buttons for the keys
a text field cannot take (Escape).

viser's page reports no key presses of its own (it has no keyboard events for the Python
side, and its HTML element does not run scripts), so the keys come from a text field: each
character typed is one key, a line break is Enter, a character deleted is Backspace.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any, Final

from belvedere.graph import GraphTopics, Node, Publisher, Subscription
from belvedere.msgs import ImageError, image_rgb

__all__ = ["KEY_BUTTONS", "WINDOW_PREFIX", "ImageWindows", "typed_keys"]

WINDOW_PREFIX: Final = "/image_window/"
"""Where highgui publishes a window's pictures (``highgui.TOPIC_PREFIX`` and a slash)."""
KEY_SUFFIX: Final = "/key"
IMAGE_TYPE: Final = "sensor_msgs/Image"
KEY_TYPE: Final = "std_msgs/Int32"
ENTER, BACKSPACE, ESCAPE, TAB = 13, 8, 27, 9
KEY_BUTTONS: Final = {"Esc": ESCAPE, "Enter": ENTER, "Space": 32, "Tab": TAB}
"""The buttons under a window's key field and the OpenCV key codes they send."""
WIDTH_RANGE: Final = (360, 640)
"""Pixels: a window's panel is as wide as its picture, within this range (a 640 x 480 picture
at its own size; a small one no narrower than rviz's docked Image panel)."""


def typed_keys(before: str, after: str) -> list[int]:
    """The keys that turned the key field's text ``before`` into ``after``, as OpenCV's
    codes: Backspace for each character taken away, then each character put in (a line break
    is Enter)."""
    start = 0
    while start < min(len(before), len(after)) and before[start] == after[start]:
        start += 1
    end = 0
    while (
        end < min(len(before), len(after)) - start
        and before[len(before) - 1 - end] == after[len(after) - 1 - end]
    ):
        end += 1
    removed = len(before) - start - end
    inserted = after[start : len(after) - end]
    return [BACKSPACE] * removed + [ENTER if ch in "\r\n" else ord(ch) for ch in inserted]


def window_name(topic: str) -> str:
    """The window a ``/image_window/<name>`` topic shows (the name as its topic spells it)."""
    return topic.removeprefix(WINDOW_PREFIX)


def is_window_topic(topic: str) -> bool:
    """A window's picture topic: one name right under ``/image_window/``."""
    return topic.startswith(WINDOW_PREFIX) and "/" not in window_name(topic)


@dataclass(eq=False)
class _Window:
    """One window's panel, its picture's subscription and its keys' publisher."""

    topic: str
    subscription: Subscription | None = None
    keys: Publisher | None = None
    panel: Any = None
    picture: Any = None
    key_field: Any = None
    typed: str = ""
    """The key field's text as last read (what is typed next is told apart from it)."""
    latest: Any = None
    drawn: Any = None
    lock: threading.Lock = field(default_factory=threading.Lock)

    def arrived(self, msg: Any) -> None:
        """A picture came (on the graph's executor thread): the next frame shows it."""
        with self.lock:
            self.latest = msg


class ImageWindows:
    """The windows of every script on the graph, as panels docked in ``docked``'s column
    (shared with the Image displays): :meth:`refresh` finds windows that came or went,
    :meth:`render` shows their newest pictures (both on the viewer's render thread)."""

    def __init__(self, node: Node, gui: Any, topics: GraphTopics, docked: list[Any]) -> None:
        self.node = node
        self.gui = gui
        self.topics = topics
        self.docked = docked
        self.windows: dict[str, _Window] = {}

    def refresh(self) -> None:
        """Open a panel for each window topic someone publishes, close the others."""
        shown = {t for t in self.topics.of_type(IMAGE_TYPE) if is_window_topic(t)}
        for topic in sorted(shown - set(self.windows)):
            self._open(topic)
        for topic in sorted(set(self.windows) - shown):
            window = self.windows.pop(topic)
            if window.panel in self.docked:
                self.docked.remove(window.panel)
            self._close(window)

    def render(self) -> None:
        for window in list(self.windows.values()):
            with window.lock:
                msg = window.latest
            if msg is None or msg is window.drawn:
                continue
            window.drawn = msg
            try:
                image = image_rgb(msg)
            except ImageError as err:
                self.node.logger.warning("window %s: %s", window.topic, err.message)
                continue
            self._show(window, image)

    def close(self) -> None:
        for window in self.windows.values():
            self._close(window)
        self.windows.clear()

    def _open(self, topic: str) -> None:
        window = _Window(topic)
        window.subscription = self.node.subscribe(topic, IMAGE_TYPE, window.arrived, queue_size=1)
        window.keys = self.node.publisher(topic + KEY_SUFFIX, KEY_TYPE)
        self.windows[topic] = window

    def _show(self, window: _Window, image: Any) -> None:
        if window.panel is not None:
            window.picture.image = image
            return
        gui = self.gui
        panel = gui.add_panel()
        with panel.add_tab(window_name(window.topic)):
            window.picture = gui.add_image(image, label=None)
            window.key_field = gui.add_text(
                "Keys",
                "",
                multiline=True,
                hint="What you type here goes to the script's cv2.waitKey, a key at a time",
            )
            window.key_field.on_update(lambda _: self._typed(window))
            buttons = gui.add_button_group("Send", list(KEY_BUTTONS))
            buttons.on_click(lambda event: self._send(window, [KEY_BUTTONS[event.target.value]]))
        if self.docked:
            panel.dock_below(self.docked[-1])
        else:
            panel.dock_right()
            panel.set_width(max(WIDTH_RANGE[0], min(WIDTH_RANGE[1], int(image.shape[1]))))
        self.docked.append(panel)
        window.panel = panel

    def _typed(self, window: _Window) -> None:
        # viser runs callbacks on a pool of threads: one at a time, each against the text
        # the last one read, so no key is sent twice or lost
        with window.lock:
            text = str(window.key_field.value)
            keys, window.typed = typed_keys(window.typed, text), text
        self._send(window, keys)

    @staticmethod
    def _send(window: _Window, keys: list[int]) -> None:
        publisher = window.keys
        if publisher is None:
            return  # the window closed while the key was on its way
        for key in keys:
            publisher.publish_data({"data": key})

    @staticmethod
    def _close(window: _Window) -> None:
        subscription, publisher = window.subscription, window.keys
        window.subscription = window.keys = None
        if subscription is not None:
            subscription.unregister()
        if publisher is not None:
            publisher.unregister()
        if window.panel is not None:
            window.panel.remove()
            window.panel = None
