"""joy's ``joy_node``: a gamepad in the browser published as sensor_msgs/Joy on ``joy`` — axes
signed as ROS's joystick driver gives them (up and left positive), inside ``~deadzone``
(0.05) zero and rescaled beyond it; changes within ``~coalesce_interval`` s (0.001) of the last
message go out as one, and the last state again every 1/``~autorepeat_rate`` s while nothing
changes, when that is above 0.

The pad is read by either page: the viewer's (a pad connected to the browser showing the
viewer; its page sends the browser's state on ``/viewer/gamepad``, which this node
subscribes to, whichever process the viewer runs in) or the node's own (its URL printed; its
port the ``~port`` parameter, 8093), for a user without the viewer."""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

from belvedere.graph import Node, Timer
from belvedere.msgs import (
    GAMEPAD_TOPIC,
    GAMEPAD_TYPE,
    GamepadState,
    build,
    gamepad_from_msg,
    types,
)
from belvedere.nodes._joy_page import JoyPage
from belvedere.nodes._registry import (
    NodeSpec,
    Session,
    Starter,
    port_param,
    stopping_on_bad_values,
)

__all__ = ["EXECUTABLES", "JOINING", "PACKAGE", "JoyPublisher", "ros_axis"]

PACKAGE = "joy"
PORT = 8093


def ros_axis(value: float, deadzone: float) -> float:
    """A browser axis (-1 up/left) as joy_node's: its sign turned, the dead zone cut out
    and the rest stretched back to [-1, 1]."""
    if abs(value) <= deadzone:
        return 0.0
    magnitude = (abs(value) - deadzone) / (1.0 - deadzone)
    return -magnitude if value > 0 else magnitude


def _number(node: Node, name: str, default: float, low: float, high: float) -> float:
    value = node.get_param(f"~{name}", default)
    if isinstance(value, bool) or not isinstance(value, int | float) or not low <= value < high:
        msg = f"parameter ~{name}: expected a number from {low} to below {high}, got {value!r}"
        raise ValueError(msg)
    return float(value)


class JoyPublisher:
    """joy_node's publishing: each state offered (on the executor thread) as a Joy message,
    coalesced and repeated as ROS's joy_node does."""

    def __init__(
        self, node: Node, *, deadzone: float, autorepeat_rate: float, coalesce_interval: float
    ) -> None:
        self.node = node
        self.deadzone = deadzone
        self.coalesce_ns = round(coalesce_interval * 1e9)
        self.pub = node.publisher("joy", "sensor_msgs/Joy", queue_size=10)
        self.joy = types().cls("sensor_msgs/Joy")
        self.frame = str(node.get_param("~frame_id", "joy"))
        self.latest: GamepadState | None = None
        self.last_sent_ns: int | None = None
        self.repeat_s = 1.0 / autorepeat_rate if autorepeat_rate > 0 else 0.0
        self.next: Timer | None = None
        """The one timer that sends next: the end of a coalescing interval or a repeat."""
        self.coalescing = False

    def offer(self, state: GamepadState | None) -> None:
        """A state came (None: the pad went, and nothing more goes out until it is back)."""
        if state == self.latest:
            return
        self.latest = state
        if self.coalescing:
            if state is None:
                self._cancel()
            return  # the interval's end sends the newest state
        self._cancel()
        if state is None:
            return
        now = self.node.now_ns()
        due = None if self.last_sent_ns is None else self.last_sent_ns + self.coalesce_ns
        if due is None or now >= due:
            self._send()
        else:
            self.coalescing = True
            self._later((due - now) / 1e9)

    def _later(self, delay_s: float) -> None:
        # the executor's own timer, not the node's: the node would keep every one-shot timer
        # of a long drive
        self.next = self.node.graph.executor.add_timer(delay_s, self._due, oneshot=True)

    def _cancel(self) -> None:
        if self.next is not None:
            self.next.cancel()
        self.next, self.coalescing = None, False

    def _due(self) -> None:
        self.next, self.coalescing = None, False
        if not self.node.closed:
            self._send()

    def _send(self) -> None:
        state = self.latest
        if state is None:
            return
        self.last_sent_ns = self.node.now_ns()
        axes = np.array([ros_axis(a, self.deadzone) for a in state.axes], np.float32)
        header = build.header(self.last_sent_ns, self.frame)
        self.pub.publish(self.joy(header, axes, np.array(state.buttons, np.int32)))
        if self.repeat_s > 0:
            self._later(self.repeat_s)


def _start(session: Session, spec: NodeSpec, node: Node) -> None:
    joy = JoyPublisher(
        node,
        deadzone=_number(node, "deadzone", 0.05, 0.0, 1.0),
        autorepeat_rate=_number(node, "autorepeat_rate", 0.0, 0.0, 1000.0),
        coalesce_interval=_number(node, "coalesce_interval", 0.001, 0.0, 60.0),
    )
    refused = [0]

    def from_viewer(msg: Any) -> None:
        valid, state = gamepad_from_msg(msg)
        if valid:
            joy.offer(state)
            return
        refused[0] += 1
        if refused[0] == 1:  # a publisher that keeps sending them would fill the log
            node.logger.warning("%s: a message that is not a gamepad's state", GAMEPAD_TOPIC)

    node.subscribe(GAMEPAD_TOPIC, GAMEPAD_TYPE, from_viewer)
    executor = node.graph.executor

    def from_page(state: GamepadState) -> None:
        executor.post(lambda: joy.offer(state))  # the page's server thread: the node's own next

    page = JoyPage(from_page, port=port_param(node, PORT))
    session.closers.append(page.close)
    node.set_param("~page_url", page.url)
    sys.stdout.write(f"joy_node: the gamepad's page is {page.url}\n")
    sys.stdout.flush()


EXECUTABLES: dict[str, Starter] = {"joy_node": stopping_on_bad_values(_start)}
JOINING = frozenset(EXECUTABLES)
