"""turtlesim's world, without the graph: turtles, their motion, their pens and the canvas.

What turtlesim (ros_tutorials, noetic) does, and this does the same way:

- The canvas is 500 by 500 pixels at 45 pixels a metre (the height of a turtle's picture), so
  the world is (500 - 1) / 45 = 11.0889 m square; x grows to the right, y upwards. turtle1 is
  spawned at its centre (5.5444, 5.5444) facing 0.
- Every update (each 16 ms: 62.5 Hz) moves each turtle, in the order of their names: its
  queued teleports first, then its velocity — zeroed once more than 1.0 s passed since its last
  ``cmd_vel`` — integrated orientation first (wrapped to [-π, π)), then position along the
  new heading: ``x += cos θ·vx·dt - sin θ·vy·dt``, ``y += sin θ·vx·dt + cos θ·vy·dt``.
- A turtle outside the canvas is clamped back to its edge with the warning ``Oh no! I hit the
  wall! (Clamping from [x=…, y=…])``, which gives the position before clamping in the
  canvas's own frame (y downwards, as turtlesim prints it).
- The pose is then reported (``linear_velocity`` is the length of (vx, vy)) and so is the
  colour of the canvas pixel under the turtle, before this update's trail is drawn.
- A turtle whose position changed draws a line from where it was with its pen (default colour
  (179, 184, 255), 3 pixels wide) unless the pen is off; a teleport draws one too. SetPen
  with ``off`` only lifts the pen (its colour stays); otherwise it sets the colour, and the
  width unless that is 0.
- ``clear`` fills the canvas with the background colour; ``reset`` removes every turtle,
  restarts the numbering and spawns turtle1 again, then clears. An empty spawn name takes the
  first free ``turtleN`` counting on from the last; a taken name is refused.
- The first update after start does nothing but note the time (turtlesim's frame does so).

turtlesim paints with Qt; here a trail is every pixel whose centre lies within the pen's
square-capped stroke, which is what Qt's aliased painter fills to within a pixel at the ends.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Final

import numpy as np

from belvedere.errors import BelvedereError

__all__ = [
    "BACKGROUND",
    "CANVAS_PX",
    "COMMAND_TIMEOUT",
    "METER_PX",
    "PEN",
    "PERIOD",
    "SIZE",
    "TurtleError",
    "TurtlePose",
    "TurtleWorld",
]

CANVAS_PX: Final = 500
METER_PX: Final = 45
SIZE: Final = (CANVAS_PX - 1) / METER_PX
"""The world's width and height in metres (11.0889)."""
PERIOD: Final = 0.016
"""Seconds between updates (turtlesim's Qt timer: 16 ms)."""
COMMAND_TIMEOUT: Final = 1.0
"""Seconds a ``cmd_vel`` lasts."""
BACKGROUND: Final = (69, 86, 255)
PEN: Final = (179, 184, 255)
PEN_WIDTH: Final = 3

Rgb = tuple[int, int, int]


class TurtleError(BelvedereError):
    """A request turtlesim refuses: a name taken, a turtle that does not exist."""


@dataclass(frozen=True)
class TurtlePose:
    """What one update reports of one turtle: its ``pose`` and its ``color_sensor``."""

    name: str
    x: float
    y: float
    theta: float
    linear_velocity: float
    angular_velocity: float
    color: Rgb


@dataclass
class _Turtle:
    x: float  # the canvas's frame: metres, y downwards
    y: float
    theta: float
    vx: float = 0.0
    vy: float = 0.0
    w: float = 0.0
    last_command: float = -math.inf
    pen: Rgb = PEN
    width: int = PEN_WIDTH
    pen_on: bool = True
    teleports: list[tuple[bool, float, float, float]] = field(default_factory=list)
    """(relative, a, b, theta): relative (linear, unused, angular) or absolute (x, y, θ)."""


class TurtleWorld:
    """turtlesim's canvas and turtles; time is what the caller passes to :meth:`update`."""

    def __init__(self, background: Rgb = BACKGROUND) -> None:
        self.canvas = np.empty((CANVAS_PX, CANVAS_PX, 3), dtype=np.uint8)
        self.turtles: dict[str, _Turtle] = {}
        self.counter = 0
        self.warnings: list[str] = []
        """Wall clamps of the last update, in turtlesim's words."""
        self._started = False
        self.clear(background)

    # --- the frame's services ------------------------------------------------------------------
    def clear(self, background: Rgb) -> None:
        self.canvas[:] = _rgb(background)

    def reset(self, background: Rgb) -> str:
        """Every turtle gone, turtle1 back at the centre, the canvas cleared; its name."""
        self.turtles.clear()
        self.counter = 0
        name = self.spawn("", SIZE / 2.0, SIZE / 2.0, 0.0)
        self.clear(background)
        return name

    def spawn(self, name: str, x: float, y: float, theta: float) -> str:
        """A new turtle at (x, y) facing ``theta``; its name (``turtleN`` when empty)."""
        _finite("spawn a turtle at", x=x, y=y, theta=theta)
        if not name:
            while True:
                self.counter += 1
                name = f"turtle{self.counter}"
                if name not in self.turtles:
                    break
        elif name in self.turtles:
            msg = f"A turtled named [{name}] already exists"  # turtlesim's words
            raise TurtleError(msg)
        self.turtles[name] = _Turtle(float(x), SIZE - float(y), float(theta))
        return name

    def kill(self, name: str) -> None:
        if self.turtles.pop(name, None) is None:
            msg = f"Tried to kill turtle [{name}], which does not exist"
            raise TurtleError(msg)

    # --- a turtle's topics and services --------------------------------------------------------
    def command(self, name: str, vx: float, vy: float, w: float, now: float) -> None:
        """``cmd_vel`` at time ``now`` (seconds); a value that is not finite stops the turtle
        rather than sending it nowhere."""
        turtle = self._turtle(name)
        if not all(math.isfinite(v) for v in (vx, vy, w)):
            vx = vy = w = 0.0
        turtle.vx, turtle.vy, turtle.w, turtle.last_command = vx, vy, w, now

    def set_pen(self, name: str, rgb: Rgb, width: int, off: bool) -> None:
        turtle = self._turtle(name)
        turtle.pen_on = not off
        if off:
            return
        turtle.pen = _rgb(rgb)
        turtle.width = width if width != 0 else 1

    def teleport_absolute(self, name: str, x: float, y: float, theta: float) -> None:
        """Done at the next update, as turtlesim queues it."""
        _finite(f"teleport {name} to", x=x, y=y, theta=theta)
        self._turtle(name).teleports.append((False, x, y, theta))

    def teleport_relative(self, name: str, linear: float, angular: float) -> None:
        _finite(f"teleport {name} by", linear=linear, angular=angular)
        self._turtle(name).teleports.append((True, linear, 0.0, angular))

    def _turtle(self, name: str) -> _Turtle:
        try:
            return self.turtles[name]
        except KeyError:
            msg = f"no turtle named [{name}]"
            raise TurtleError(msg) from None

    # --- time ----------------------------------------------------------------------------------
    def update(self, now: float, dt: float = PERIOD) -> list[TurtlePose]:
        """One update at time ``now``: every turtle moved by ``dt`` seconds; their reports."""
        self.warnings = []
        if not self._started:
            self._started = True
            return []
        return [self._move(name, self.turtles[name], now, dt) for name in sorted(self.turtles)]

    def _move(self, name: str, t: _Turtle, now: float, dt: float) -> TurtlePose:
        for relative, a, b, theta in t.teleports:
            old = (t.x, t.y)
            if relative:
                t.theta += theta
                t.x += math.cos(t.theta) * a
                t.y -= math.sin(t.theta) * a
            else:
                t.x, t.y, t.theta = a, max(0.0, SIZE - b), theta
            self._draw(t, old)
        t.teleports.clear()
        if now - t.last_command > COMMAND_TIMEOUT:
            t.vx = t.vy = t.w = 0.0
        old = (t.x, t.y)
        theta = t.theta + t.w * dt
        t.theta = theta - 2.0 * math.pi * math.floor((theta + math.pi) / (2.0 * math.pi))
        cos, sin = math.cos(t.theta), math.sin(t.theta)
        t.x += cos * t.vx * dt - sin * t.vy * dt
        t.y -= cos * t.vy * dt + sin * t.vx * dt
        if not (0.0 <= t.x <= SIZE and 0.0 <= t.y <= SIZE):
            self.warnings.append(f"Oh no! I hit the wall! (Clamping from [x={t.x:f}, y={t.y:f}])")
        t.x, t.y = min(max(t.x, 0.0), SIZE), min(max(t.y, 0.0), SIZE)
        col, row = (_round(v * METER_PX) for v in (t.x, t.y))
        pixel = self.canvas[min(row, CANVAS_PX - 1), min(col, CANVAS_PX - 1)]
        pose = TurtlePose(
            name,
            t.x,
            SIZE - t.y,
            t.theta,
            math.hypot(t.vx, t.vy),
            t.w,
            (int(pixel[0]), int(pixel[1]), int(pixel[2])),
        )
        if (t.x, t.y) != old:
            self._draw(t, old)
        return pose

    def _draw(self, t: _Turtle, old: tuple[float, float]) -> None:
        if t.pen_on:
            stroke(self.canvas, (old[0] * METER_PX, old[1] * METER_PX),
                   (t.x * METER_PX, t.y * METER_PX), t.width, t.pen)  # fmt: skip

    # --- pictures ------------------------------------------------------------------------------
    def image(self) -> np.ndarray[Any, np.dtype[np.uint8]]:
        """The window as turtlesim shows it: the canvas with each turtle drawn on it (a shell
        and a head towards its heading, in place of turtlesim's pictures)."""
        picture = self.canvas.copy()
        for name in sorted(self.turtles):
            t = self.turtles[name]
            cx, cy = t.x * METER_PX, t.y * METER_PX
            head = (cx + 13.0 * math.cos(t.theta), cy - 13.0 * math.sin(t.theta))
            _disk(picture, head, 5.0, (120, 200, 90))
            _disk(picture, (cx, cy), 11.0, (40, 120, 50))
            _disk(picture, (cx, cy), 6.0, (90, 170, 70))
        return picture


def _finite(doing: str, **values: float) -> None:
    """A request with a value that is not a number is refused (turtlesim would put the
    turtle nowhere, and every later pose with it)."""
    if not all(math.isfinite(v) for v in values.values()):
        given = ", ".join(f"{k}={v}" for k, v in values.items())
        msg = f"cannot {doing} {given}: not a number"
        raise TurtleError(msg)


def _round(value: float) -> int:
    """Qt's qRound (a point's pixel): halves away from zero."""
    return math.floor(value + 0.5) if value >= 0 else -math.floor(-value + 0.5)


def _rgb(rgb: Rgb) -> Rgb:
    r, g, b = (int(v) for v in rgb)
    if not all(0 <= v <= 255 for v in (r, g, b)):
        msg = f"a colour is three values 0-255, not {rgb}"
        raise TurtleError(msg)
    return (r, g, b)


def stroke(
    canvas: np.ndarray[Any, np.dtype[np.uint8]],
    start: tuple[float, float],
    end: tuple[float, float],
    width: int,
    rgb: Rgb,
) -> None:
    """A line ``width`` pixels wide with square caps from ``start`` to ``end`` (pixels,
    column and row), clipped to the canvas."""
    (x0, y0), (x1, y1) = start, end
    half = width / 2.0
    left, right = max(math.floor(min(x0, x1) - half), 0), math.ceil(max(x0, x1) + half)
    top, bottom = max(math.floor(min(y0, y1) - half), 0), math.ceil(max(y0, y1) + half)
    right, bottom = min(right, canvas.shape[1] - 1), min(bottom, canvas.shape[0] - 1)
    if left > right or top > bottom:
        return
    rows, cols = np.mgrid[top : bottom + 1, left : right + 1]
    dx, dy = x1 - x0, y1 - y0
    length = math.hypot(dx, dy)
    ux, uy = (dx / length, dy / length) if length > 0 else (1.0, 0.0)
    mx, my = (x0 + x1) / 2.0, (y0 + y1) / 2.0
    along = (cols - mx) * ux + (rows - my) * uy
    across = -(cols - mx) * uy + (rows - my) * ux
    inside = (np.abs(along) <= length / 2.0 + half) & (np.abs(across) <= half)
    canvas[top : bottom + 1, left : right + 1][inside] = rgb


def _disk(
    canvas: np.ndarray[Any, np.dtype[np.uint8]],
    centre: tuple[float, float],
    radius: float,
    rgb: Rgb,
) -> None:
    cx, cy = centre
    left, right = max(math.floor(cx - radius), 0), min(math.ceil(cx + radius), CANVAS_PX - 1)
    top, bottom = max(math.floor(cy - radius), 0), min(math.ceil(cy + radius), CANVAS_PX - 1)
    if left > right or top > bottom:
        return
    rows, cols = np.mgrid[top : bottom + 1, left : right + 1]
    inside = (cols - cx) ** 2 + (rows - cy) ** 2 <= radius * radius
    canvas[top : bottom + 1, left : right + 1][inside] = rgb
