"""Keyboard layouts for driving a robot: what each key does to the commanded Twist.

``twist_keyboard`` behaves as ``teleop_twist_keyboard``: u i o / j k l / m , . move, Shift
for holonomic moves, t/b up/down, q/z w/x e/c scale the speeds by 10 %, any other key stops.
``mbot`` behaves as the course's ``mbot_teleop`` (itself ``turtlebot_teleop_key``): the same
directions without Shift, speeds that ramp towards their target every 0.1 s, space or k to stop
at once, and a smooth stop after 0.5 s without a key.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Protocol

__all__ = ["LAYOUTS", "Layout", "MbotTeleop", "Output", "TurtleKeys", "TwistKeyboard"]

CTRL_C: Final = "\x03"

_TWIST_HELP: Final = """
Reading from the keyboard and publishing to Twist!
---------------------------
Moving around:
   u    i    o
   j    k    l
   m    ,    .

For holonomic mode (strafing), hold down the shift key:
---------------------------
   U    I    O
   J    K    L
   M    <    >

t : up (+z)
b : down (-z)

anything else : stop

q/z : increase/decrease max speeds by 10%
w/x : increase/decrease only linear speed by 10%
e/c : increase/decrease only angular speed by 10%

CTRL-C to quit
"""

_MBOT_HELP: Final = """
Control mbot!
---------------------------
Moving around:
   u    i    o
   j    k    l
   m    ,    .

q/z : increase/decrease max speeds by 10%
w/x : increase/decrease only linear speed by 10%
e/c : increase/decrease only angular speed by 10%
space key, k : force stop
anything else : stop smoothly

CTRL-C to quit
"""

# key -> (x, y, z, turn) directions
_MOVES: Final = {
    "i": (1, 0, 0, 0),
    "o": (1, 0, 0, -1),
    "j": (0, 0, 0, 1),
    "l": (0, 0, 0, -1),
    "u": (1, 0, 0, 1),
    ",": (-1, 0, 0, 0),
    ".": (-1, 0, 0, 1),
    "m": (-1, 0, 0, -1),
}
_HOLONOMIC: Final = {
    "O": (1, -1, 0, 0),
    "I": (1, 0, 0, 0),
    "J": (0, 1, 0, 0),
    "L": (0, -1, 0, 0),
    "U": (1, 1, 0, 0),
    "<": (-1, 0, 0, 0),
    ">": (-1, -1, 0, 0),
    "M": (-1, 1, 0, 0),
    "t": (0, 0, 1, 0),
    "b": (0, 0, -1, 0),
}
# key -> (linear factor, angular factor)
_SCALES: Final = {
    "q": (1.1, 1.1),
    "z": (0.9, 0.9),
    "w": (1.1, 1.0),
    "x": (0.9, 1.0),
    "e": (1.0, 1.1),
    "c": (1.0, 0.9),
}


@dataclass(frozen=True)
class Output:
    """What one key (or one quiet interval) leads to."""

    twist: tuple[float, float, float, float] | None = None
    """(linear x, y, z, angular z) to publish, or None to publish nothing."""
    text: str | None = None
    """A line for the terminal."""
    quit: bool = False


class Layout(Protocol):
    help: str
    poll: float | None
    """Seconds to wait for a key before :meth:`idle` (None: wait forever)."""

    def key(self, key: str) -> Output: ...
    def idle(self) -> Output: ...


class TwistKeyboard:
    """teleop_twist_keyboard."""

    help = _TWIST_HELP

    def __init__(self, speed: float = 0.5, turn: float = 1.0, key_timeout: float = 0.0) -> None:
        self.speed = speed
        self.turn = turn
        self.direction = (0, 0, 0, 0)
        self.status = 0
        self.poll = key_timeout if key_timeout > 0 else None

    def _twist(self) -> tuple[float, float, float, float]:
        x, y, z, th = self.direction
        return (x * self.speed, y * self.speed, z * self.speed, th * self.turn)

    def key(self, key: str) -> Output:
        if key == CTRL_C:
            return Output(quit=True)
        text = None
        if key in _MOVES or key in _HOLONOMIC:
            self.direction = _MOVES.get(key) or _HOLONOMIC[key]
        elif key in _SCALES:
            lin, ang = _SCALES[key]
            self.speed *= lin
            self.turn *= ang
            text = f"currently:\tspeed {self.speed:g}\tturn {self.turn:g} "
            if self.status == 14:
                text = self.help + "\n" + text
            self.status = (self.status + 1) % 15
        else:
            self.direction = (0, 0, 0, 0)
        return Output(self._twist(), text)

    def idle(self) -> Output:
        """No key within ``key_timeout``: stop (publishing only if moving)."""
        if self.direction == (0, 0, 0, 0):
            return Output()
        self.direction = (0, 0, 0, 0)
        return Output(self._twist())


class MbotTeleop:
    """The course's mbot_teleop: ramped speeds, published every 0.1 s."""

    help = _MBOT_HELP
    poll: float | None = 0.1
    LINEAR_STEP = 0.02
    ANGULAR_STEP = 0.1
    IDLE_STOP = 4  # quiet polls before a smooth stop

    def __init__(self, speed: float = 0.2, turn: float = 1.0) -> None:
        self.speed = speed
        self.turn = turn
        self.x = 0
        self.th = 0
        self.quiet = 0
        self.status = 0
        self.control = (0.0, 0.0)

    def key(self, key: str) -> Output:
        if key == CTRL_C:
            return Output(quit=True)
        text = None
        if key in _MOVES:
            self.x, _, _, self.th = _MOVES[key]
            self.quiet = 0
        elif key in _SCALES:
            lin, ang = _SCALES[key]
            self.speed *= lin
            self.turn *= ang
            self.quiet = 0
            text = f"currently:\tspeed {self.speed:g}\tturn {self.turn:g} "
            if self.status == 14:
                text = self.help + "\n" + text
            self.status = (self.status + 1) % 15
        elif key in (" ", "k"):
            self.x = self.th = 0
            self.control = (0.0, 0.0)
        else:
            return self.idle()
        return Output(self._ramp(), text)

    def idle(self) -> Output:
        self.quiet += 1
        if self.quiet > self.IDLE_STOP:
            self.x = self.th = 0
        return Output(self._ramp())

    def _ramp(self) -> tuple[float, float, float, float]:
        speed = _towards(self.control[0], self.speed * self.x, self.LINEAR_STEP)
        turn = _towards(self.control[1], self.turn * self.th, self.ANGULAR_STEP)
        self.control = (speed, turn)
        return (speed, 0.0, 0.0, turn)


def _towards(current: float, target: float, step: float) -> float:
    if target > current:
        return min(target, current + step)
    if target < current:
        return max(target, current - step)
    return target


_TURTLE_HELP: Final = """Reading from keyboard
---------------------------
Use arrow keys to move the turtle. 'q' to quit."""

# An arrow key is ESC [ A..D; turtlesim's teleop reads byte by byte and acts on the last one.
_ARROWS: Final = {"A": (1.0, 0.0), "B": (-1.0, 0.0), "C": (0.0, -1.0), "D": (0.0, 1.0)}


class TurtleKeys:
    """turtlesim's ``turtle_teleop_key``: each arrow key sends one command (linear or angular
    times its scale, 2.0 by default), other keys nothing; q quits."""

    help = _TURTLE_HELP
    poll: float | None = None

    def __init__(self, scale_linear: float = 2.0, scale_angular: float = 2.0) -> None:
        self.scale_linear = scale_linear
        self.scale_angular = scale_angular

    def key(self, key: str) -> Output:
        if key in ("q", CTRL_C):
            return Output(quit=True)
        if key not in _ARROWS:
            return Output()
        linear, angular = _ARROWS[key]
        return Output((self.scale_linear * linear, 0.0, 0.0, self.scale_angular * angular))

    def idle(self) -> Output:
        return Output()


LAYOUTS: Final = {"twist_keyboard": TwistKeyboard, "mbot": MbotTeleop}
