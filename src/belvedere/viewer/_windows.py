"""OpenCV's windows of the graph's scripts, each a panel of the viewer.

A script's ``cv2.imshow(name, image)`` publishes ``/image_window/<name>`` and the window's
name on ``/image_window/<name>/name`` (:mod:`belvedere.ros1.highgui`); the viewer shows
every such topic it finds on the graph, without being asked, in a panel titled with the
window's name, and takes the panel away when the topic has no publisher left
(``cv2.destroyWindow``, or the script ended). Keys go back to the script's ``cv2.waitKey``
on ``/image_window/<name>/key`` (std_msgs/Int32, OpenCV's key codes).

viser tells the Python side of no key presses, so each window's panel has a key field (a
viser text field: each character typed into it is one key, a line break Enter, a character
deleted Backspace) and buttons for keys a text field cannot take (Escape). A small script
sent to the page (viser's own way to run JavaScript there, as its Plotly element loads
Plotly) makes a key pressed while the window's panel has focus — after a click on its
picture, as one clicks an OpenCV window — go into that field too, so the user presses
``q`` or Escape on the picture as with OpenCV. Keys pressed elsewhere in the page stay the
page's (viser moves the 3D camera with some).
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field
from typing import Any, Final

from belvedere.graph import GraphTopics, Node, Publisher, Subscription
from belvedere.msgs import ImageError, image_rgb
from belvedere.ros1.highgui import KEY_SUFFIX, KEY_TYPE, NAME_SUFFIX, NAME_TYPE, TOPIC_PREFIX
from belvedere.viewer._page import run_in_page

__all__ = ["KEY_BUTTONS", "WINDOW_PREFIX", "ImageWindows", "typed_keys"]

WINDOW_PREFIX: Final = TOPIC_PREFIX + "/"
IMAGE_TYPE: Final = "sensor_msgs/Image"
NAME_LIMIT: Final = 200
"""Characters of a window's name its panel's title shows (a tab, not a page of text)."""
NAME_WAIT_S: Final = 1.0
"""Seconds a window's panel waits for its name (latched, it comes with the first pictures);
without it, the panel is titled as the topic spells the name."""
ENTER, BACKSPACE, ESCAPE, TAB = 13, 8, 27, 9
KEY_BUTTONS: Final = {"Esc": ESCAPE, "Enter": ENTER, "Space": 32, "Tab": TAB}
"""The buttons under a window's key field and the OpenCV key codes they send."""
WIDTH_RANGE: Final = (360, 640)
"""Pixels: a window's panel is as wide as its picture, within this range (a 640 x 480 picture
at its own size; a small one no narrower than rviz's docked Image panel)."""


PAGE_KEYS: Final = """
if (!window.__belvedereWindowKeys) {
  window.__belvedereWindowKeys = true;
  // The panel of the last click: the nearest box around it that holds a key field and no
  // 3D view (a window's panel; never the control panel or the page as a whole).
  let field = null;
  const keyFields = (box) =>
    [...box.querySelectorAll("textarea")].filter((t) => t.offsetParent !== null);
  window.addEventListener("pointerdown", (event) => {
    field = null;
    for (let box = event.target; box instanceof Element; box = box.parentElement) {
      if (box.querySelector("canvas")) break;
      const found = keyFields(box);
      if (found.length > 0) {
        field = found.length === 1 ? found[0] : null;
        break;
      }
    }
  }, true);
  const named = {Enter: "\\n", Escape: "\\x1b", Tab: "\\t", Backspace: "\\b"};
  window.addEventListener("keydown", (event) => {
    const target = event.target;
    if (field === null || !field.isConnected || event.ctrlKey || event.altKey ||
        event.metaKey || target instanceof HTMLInputElement ||
        target instanceof HTMLTextAreaElement || target instanceof HTMLSelectElement) {
      return;  // typed into a field (the key field itself sends it), or not for a window
    }
    const text = event.key.length === 1 ? event.key : named[event.key];
    if (text === undefined) return;
    event.preventDefault();
    event.stopPropagation();  // a window's key, not the 3D camera's
    // React reads a field's value from its input event: set it as typing does.
    const setter = Object.getOwnPropertyDescriptor(HTMLTextAreaElement.prototype, "value").set;
    setter.call(field, field.value + text);
    field.dispatchEvent(new Event("input", {bubbles: true}));
  }, true);
}
"""
"""Sent once to every page of the viewer: a key pressed while a window's panel has focus
goes into that panel's key field (Enter, Escape, Tab and Backspace as their control
characters). Static text: nothing of a window's name or content is in it."""


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


def send_page_keys(gui: Any) -> None:
    """Have every page of ``gui``'s server (those open and those to come) send the keys
    pressed on a window's panel into its key field."""
    run_in_page(gui, PAGE_KEYS)


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
    names: Subscription | None = None
    keys: Publisher | None = None
    opened_s: float = field(default_factory=time.monotonic)
    name: str | None = None
    """The window's name as the script spelled it (when it has come)."""
    panel: Any = None
    picture: Any = None
    key_field: Any = None
    typed: str = ""
    """The key field's text as last read (what is typed next is told apart from it)."""
    latest: Any = None
    drawn: Any = None
    received: int = 0
    """Pictures that came (the benchmark's count)."""
    lock: threading.Lock = field(default_factory=threading.Lock)

    def arrived(self, msg: Any) -> None:
        """A picture came (on the graph's executor thread): the next frame shows it."""
        with self.lock:
            self.latest = msg
            self.received += 1

    def named(self, msg: Any) -> None:
        with self.lock:
            self.name = str(msg.data)[:NAME_LIMIT]


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
        send_page_keys(gui)

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
                msg, name = window.latest, window.name
            waited = time.monotonic() - window.opened_s
            if window.panel is None and name is None and waited < NAME_WAIT_S:
                continue  # its name is on its way
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
        window.names = self.node.subscribe(topic + NAME_SUFFIX, NAME_TYPE, window.named)
        window.keys = self.node.publisher(topic + KEY_SUFFIX, KEY_TYPE)
        self.windows[topic] = window

    def _show(self, window: _Window, image: Any) -> None:
        if window.panel is not None:
            window.picture.image = image
            return
        gui = self.gui
        panel = gui.add_panel()
        with panel.add_tab(window.name or window_name(window.topic)):
            window.picture = gui.add_image(image, label=None)
            window.key_field = gui.add_text(
                "Keys",
                "",
                multiline=True,
                hint="Keys for the script's cv2.waitKey: type here, or click the picture and "
                "press keys",
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
        # the last one read, so no key is sent twice, lost or out of order
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
        subscriptions, publisher = (window.subscription, window.names), window.keys
        window.subscription = window.names = window.keys = None
        for subscription in subscriptions:
            if subscription is not None:
                subscription.unregister()
        if publisher is not None:
            publisher.unregister()
        if window.panel is not None:
            window.panel.remove()
            window.panel = None
