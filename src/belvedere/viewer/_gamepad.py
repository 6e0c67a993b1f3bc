"""The gamepad of the browser showing the viewer, for joy_node.

viser tells the Python side of no gamepad, so a small script sent to the page (viser's own
way to run JavaScript there, as its Plotly element loads Plotly) reads the first pad through
the Gamepad API 50 times a second and, when its state changed, writes it as JSON into the
Gamepad folder's State field (a viser text field the user cannot type into: React takes the
value from the input event, as when typing, and viser sends it here). The viewer checks the
state and publishes it, as the browser gives it, on ``/viewer/gamepad`` (sensor_msgs/Joy,
``header.frame_id`` the pad's id; empty when the pad went), where joy_node — in this process
or another — takes it and publishes ``joy`` with its dead zone, coalescing and repeats.

The folder shows only while something subscribes to ``/viewer/gamepad`` (a joy_node runs),
with a status line naming the pad connected.
"""

from __future__ import annotations

import threading
from typing import Any, Final

from belvedere.graph import Node
from belvedere.msgs import GAMEPAD_TOPIC, GAMEPAD_TYPE, GamepadState, gamepad_from_json
from belvedere.viewer._page import run_in_page

__all__ = ["PAGE_GAMEPAD", "STATE_PREFIX", "ViewerGamepad", "pad_markdown", "parse_field"]

STATE_PREFIX: Final = "gamepad:"
"""What the State field's text starts with: the page's script finds the field by it."""
NO_PAD: Final = "No gamepad: connect one to this computer and press a button."
REFRESH_S: Final = 0.5
"""Seconds (graph time) between looks at whether a joy_node listens."""

PAGE_GAMEPAD: Final = """
if (!window.__belvedereGamepad) {
  window.__belvedereGamepad = true;
  let last = "";  // nothing to tell until a pad is seen: another tab's pad stays the one read
  const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
  setInterval(() => {
    const pads = Array.from(navigator.getGamepads ? navigator.getGamepads() : [])
      .filter((p) => p && p.connected !== false);
    const pad = pads[0];
    const state = pad ? JSON.stringify({
      id: String(pad.id),
      axes: Array.from(pad.axes, (a) => Math.round(a * 1e4) / 1e4),
      buttons: Array.from(pad.buttons, (b) => (b.pressed ? 1 : 0)),
    }) : "";
    if (state === last) return;
    const field = [...document.querySelectorAll("input")]
      .find((i) => i.value.startsWith("__PREFIX__"));
    if (field === undefined) return;  // no joy_node listens (the folder is hidden): later
    setter.call(field, "__PREFIX__" + state);
    field.dispatchEvent(new Event("input", {bubbles: true}));
    last = state;
  }, 20);
}
""".replace("__PREFIX__", STATE_PREFIX)
"""Sent once to every page of the viewer. Static text: nothing from the graph is in it, and
nothing the page sends back is run — it is parsed as JSON and checked."""


def parse_field(text: str) -> tuple[bool, GamepadState | None]:
    """(valid, state) of the State field's text: ``gamepad:`` alone is no pad (valid, None);
    anything else not a state the page could have sent is (False, None)."""
    if not text.startswith(STATE_PREFIX):
        return False, None
    body = text[len(STATE_PREFIX) :]
    if not body:
        return True, None
    state = gamepad_from_json(body)
    return state is not None, state


def pad_markdown(state: GamepadState | None) -> str:
    """The status line: the pad's id as plain text (every ASCII punctuation escaped, control
    characters dropped: an id is the browser's, shown, never rendered as markup)."""
    if state is None:
        return NO_PAD
    shown = "".join(
        f"\\{ch}" if ch.isascii() and not ch.isalnum() and ch != " " else ch
        for ch in state.id
        if ch.isprintable()
    )
    return f"Gamepad: {shown or '(no name)'}"


class ViewerGamepad:
    """The Gamepad folder of the viewer's panel and its publisher."""

    def __init__(self, node: Node, gui: Any) -> None:
        self.node = node
        self.pub = node.publisher(GAMEPAD_TOPIC, GAMEPAD_TYPE, queue_size=10)
        self.lock = threading.Lock()
        self.state: GamepadState | None = None
        self.rejected = 0
        """States the page sent that were not ones (a page changed by hand)."""
        self.folder = gui.add_folder("Gamepad", visible=False)
        with self.folder:
            self.status = gui.add_markdown(NO_PAD)
            self.field = gui.add_text(
                "State",
                STATE_PREFIX,
                disabled=True,
                hint="The browser's gamepad as this page reads it, sent to joy_node",
            )
        self.field.on_update(lambda _: self._changed())
        run_in_page(gui, PAGE_GAMEPAD)
        node.timer(REFRESH_S, self.refresh)

    def refresh(self) -> None:
        """Show the folder while a joy_node listens (the page writes only into a shown one)."""
        wanted = self.pub.wanted
        if self.folder.visible != wanted:
            self.folder.visible = wanted

    def _changed(self) -> None:
        # viser runs callbacks on a pool of threads: one at a time, each reading the field's
        # newest text, so an older state never goes out after a newer one
        with self.lock:
            valid, state = parse_field(str(self.field.value))
            if not valid:
                self.rejected += 1
                if self.rejected == 1:
                    self.node.logger.warning("gamepad: the page sent a state that is not one")
                return
            if state == self.state:
                return
            self.state = state
            self.status.content = pad_markdown(state)
            if state is None:
                self.pub.publish_data({})
            else:
                self.pub.publish_data(
                    {
                        "header": {"frame_id": state.id},
                        "axes": list(state.axes),
                        "buttons": list(state.buttons),
                    }
                )
