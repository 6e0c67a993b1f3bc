"""turtlesim: the course's first simulator (``turtlesim_node``) and its tutorials'
executables (``turtle_teleop_key``, ``mimic``, ``draw_square``).

``turtlesim_node`` wires :class:`~belvedere.sim.turtlesim.TurtleWorld` (where the semantics
are written down) to turtlesim's names, in the node's namespace: the services ``clear``,
``reset`` (std_srvs/Empty), ``spawn`` and ``kill``; for each turtle N, ``turtleN/cmd_vel``
(in), ``turtleN/pose`` and ``turtleN/color_sensor`` (out, every update) and the services
``turtleN/set_pen``, ``turtleN/teleport_absolute`` and ``turtleN/teleport_relative``. Its
private parameters ``~background_r``, ``~background_g`` and ``~background_b`` are set to 69,
86, 255 at start unless already set, and read again by ``clear`` and ``reset``. Updates run
every 16 ms of the graph's time, so a run in simulated time is deterministic.
"""

from __future__ import annotations

import contextlib
import logging
import math
import sys
import threading
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from belvedere.graph import (
    GraphError,
    Node,
    Publisher,
    ServiceFailedError,
    ServiceServer,
    Subscription,
)
from belvedere.msgs import types
from belvedere.nodes._keyboard import drive_from_terminal
from belvedere.nodes._registry import NodeSpec, Session, Starter
from belvedere.sim.turtlesim import (
    BACKGROUND,
    METER_PX,
    PERIOD,
    SIZE,
    TurtleError,
    TurtleWorld,
)

__all__ = ["EXECUTABLES", "JOINING", "NAMES", "PACKAGE", "TurtlesimNode"]

PACKAGE = "turtlesim"
logger = logging.getLogger("belvedere.nodes.turtlesim")

_TWIST = "geometry_msgs/Twist"


class TurtlesimNode:
    """``turtlesim_node`` on ``node``: the world, its services and each turtle's names."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.lock = threading.Lock()
        """Held while the world changes: the viewer's thread takes its picture between."""
        for channel, value in zip("rgb", BACKGROUND, strict=True):
            if not node.has_param(f"~background_{channel}"):
                node.set_param(f"~background_{channel}", value)
        self.world = TurtleWorld(self.background())
        self.names: dict[str, list[Publisher | Subscription | ServiceServer]] = {}
        self.publishers: dict[str, tuple[Publisher, Publisher]] = {}
        node.service("clear", "std_srvs/Empty", self._clear)
        node.service("reset", "std_srvs/Empty", self._reset)
        node.service("spawn", "turtlesim/Spawn", self._spawn)
        node.service("kill", "turtlesim/Kill", self._kill)
        node.logger.info("Starting turtlesim with node name %s", node.full_name)
        centre = SIZE / 2.0
        self._spawned(self.world.spawn("", centre, centre, 0.0), centre, centre, 0.0)
        node.timer(PERIOD, self._update)
        self.cmd_vel = node.resolve("turtle1/cmd_vel")
        """What the viewer's teleop drives, as turtle_teleop_key does."""

    def picture(self) -> tuple[np.ndarray[Any, np.dtype[np.uint8]], float]:
        """turtlesim's window (:class:`belvedere.viewer.Canvas`)."""
        with self.lock:
            return self.world.image(), 1.0 / METER_PX

    def background(self) -> tuple[int, int, int]:
        """``~background_r/g/b`` as turtlesim reads them (roscpp's integer parameters: a
        double is rounded, as roscpp rounds it): 0-255 each, else its default, with a warning
        naming the parameter (Qt would wrap 300 round to 44)."""
        rgb = []
        for channel, default in zip("rgb", BACKGROUND, strict=True):
            value = self.node.get_param(f"~background_{channel}", default)
            if isinstance(value, float) and math.isfinite(value):
                value = math.floor(value) if math.fmod(value, 1.0) < 0.5 else math.ceil(value)
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 255:
                self.node.logger.warning(
                    "%s/background_%s is %r, not an integer 0-255: using %d",
                    self.node.full_name,
                    channel,
                    value,
                    default,
                )
                value = default
            rgb.append(value)
        return (rgb[0], rgb[1], rgb[2])

    @contextlib.contextmanager
    def _refusing(self, service: str) -> Iterator[None]:
        """What the world refuses is logged as turtlesim logs it, and the service call fails
        (turtlesim's handler returns false)."""
        try:
            yield
        except TurtleError as err:
            self.node.logger.error("%s", err.message)
            raise ServiceFailedError(self.node.resolve(service), err.message) from None

    # --- the frame's services ------------------------------------------------------------------
    def _clear(self, request: Any) -> None:
        del request
        self.node.logger.info("Clearing turtlesim.")
        background = self.background()
        with self.lock:
            self.world.clear(background)

    def _reset(self, request: Any) -> None:
        del request
        self.node.logger.info("Resetting turtlesim.")
        for name in list(self.names):
            self._forget(name)
        background = self.background()
        with self.lock:
            name = self.world.reset(background)
        self._spawned(name, SIZE / 2.0, SIZE / 2.0, 0.0)

    def _spawn(self, request: Any) -> dict[str, str]:
        x, y, theta = float(request.x), float(request.y), float(request.theta)
        with self._refusing("spawn"), self.lock:
            name = self.world.spawn(str(request.name), x, y, theta)
        self._spawned(name, x, y, theta)
        return {"name": name}

    def _kill(self, request: Any) -> None:
        name = str(request.name)
        with self._refusing("kill"), self.lock:
            self.world.kill(name)
        self._forget(name)

    # --- each turtle's names -------------------------------------------------------------------
    def _spawned(self, name: str, x: float, y: float, theta: float) -> None:
        node, world = self.node, self.world

        def on_cmd(msg: Any) -> None:
            if name in world.turtles:
                world.command(name, msg.linear.x, msg.linear.y, msg.angular.z, node.now())

        def set_pen(req: Any) -> None:
            world.set_pen(name, (req.r, req.g, req.b), int(req.width), bool(req.off))

        def absolute(req: Any) -> None:
            with self._refusing(f"{name}/teleport_absolute"), self.lock:
                world.teleport_absolute(name, float(req.x), float(req.y), float(req.theta))

        def relative(req: Any) -> None:
            with self._refusing(f"{name}/teleport_relative"), self.lock:
                world.teleport_relative(name, float(req.linear), float(req.angular))

        pose = node.publisher(f"{name}/pose", "turtlesim/Pose", queue_size=1)
        color = node.publisher(f"{name}/color_sensor", "turtlesim/Color", queue_size=1)
        self.publishers[name] = (pose, color)
        self.names[name] = [
            pose,
            color,
            node.subscribe(f"{name}/cmd_vel", _TWIST, on_cmd, queue_size=1),
            node.service(f"{name}/set_pen", "turtlesim/SetPen", set_pen),
            node.service(f"{name}/teleport_absolute", "turtlesim/TeleportAbsolute", absolute),
            node.service(f"{name}/teleport_relative", "turtlesim/TeleportRelative", relative),
        ]
        node.logger.info("Spawning turtle [%s] at x=[%f], y=[%f], theta=[%f]", name, x, y, theta)

    def _forget(self, name: str) -> None:
        graph = self.node.graph
        self.publishers.pop(name, None)
        for handle in self.names.pop(name, []):
            if isinstance(handle, Publisher):
                graph.remove_publisher(handle)
            elif isinstance(handle, Subscription):
                graph.remove_subscription(handle)
            else:
                graph.remove_service(handle)

    def _update(self) -> None:
        with self.lock:
            reports = self.world.update(self.node.now())
        pose_msg, color_msg = types().cls("turtlesim/Pose"), types().cls("turtlesim/Color")
        for r in reports:
            pose, color = self.publishers[r.name]
            if pose.wanted:  # nobody listening costs nothing
                pose.publish(pose_msg(r.x, r.y, r.theta, r.linear_velocity, r.angular_velocity))
            if color.wanted:
                color.publish(color_msg(*r.color))
        for warning in self.world.warnings:
            self.node.logger.warning("%s", warning)


class _Mimic:
    """mimic: ``input/pose`` → ``output/cmd_vel`` (remap ``input`` and ``output`` to pair two
    turtles): each pose's speeds sent on as a command."""

    def __init__(self, node: Node) -> None:
        # roscpp remaps a NodeHandle's namespace as it makes it: ``input:=turtle1`` moves
        # everything under it
        output, input_ = node.resolve("output"), node.resolve("input")
        self.pub = node.publisher(f"{output}/cmd_vel", _TWIST, queue_size=1)
        node.subscribe(f"{input_}/pose", "turtlesim/Pose", self._on_pose, queue_size=1)

    def _on_pose(self, pose: Any) -> None:
        self.pub.publish_data(
            {"linear": {"x": pose.linear_velocity}, "angular": {"z": pose.angular_velocity}}
        )


_PI = 3.141592  # draw_square's own, shorter π: it decides where its turns end


class _DrawSquare:
    """draw_square: resets turtlesim, then drives turtle1 round a 2 m square for ever —
    forward at 1 m/s to a goal 2 m ahead, stop, turn at 0.4 rad/s by a quarter turn, stop —
    deciding every 16 ms from the latest ``turtle1/pose``."""

    def __init__(self, node: Node) -> None:
        self.node = node
        self.pose: Any = None
        self.state = "forward"
        self.goal: tuple[float, float, float] | None = None
        node.subscribe("turtle1/pose", "turtlesim/Pose", self._on_pose, queue_size=1)
        self.pub = node.publisher("turtle1/cmd_vel", _TWIST, queue_size=1)
        node.timer(0.016, self._tick)
        try:
            node.call_service("reset", "std_srvs/Empty")
        except GraphError as err:  # draw_square ignores a failed reset and waits for a pose
            node.logger.warning("could not reset turtlesim: %s", err.message)

    def _on_pose(self, pose: Any) -> None:
        self.pose = pose

    def _command(self, linear: float, angular: float) -> None:
        self.pub.publish_data({"linear": {"x": linear}, "angular": {"z": angular}})

    def _ahead(self) -> tuple[float, float, float]:
        p = self.pose
        return (math.cos(p.theta) * 2 + p.x, math.sin(p.theta) * 2 + p.y, p.theta)

    def _reached(self) -> bool:
        p, goal = self.pose, self.goal
        assert goal is not None
        near = abs(p.x - goal[0]) < 0.1 and abs(p.y - goal[1]) < 0.1
        return bool(near and abs(p.theta - goal[2]) < 0.01)

    def _stopped(self) -> bool:
        return bool(self.pose.angular_velocity < 0.0001 and self.pose.linear_velocity < 0.0001)

    def _new_goal(self, goal: tuple[float, float, float]) -> None:
        self.goal = goal
        self.node.logger.info("New goal [%f %f, %f]", *goal)

    def _tick(self) -> None:
        if self.pose is None:
            return
        if self.goal is None:
            self._new_goal(self._ahead())
        if self.state in ("forward", "turn"):
            if self._reached():
                self.state = "stop_" + self.state
                self._command(0.0, 0.0)
            else:
                forward = self.state == "forward"
                self._command(1.0 if forward else 0.0, 0.0 if forward else 0.4)
            return
        if not self._stopped():
            self._command(0.0, 0.0)
            return
        self.node.logger.info("Reached goal")
        p = self.pose
        if self.state == "stop_forward":
            self.state = "turn"
            theta = math.fmod(p.theta + _PI / 2.0, 2 * _PI)
            self._new_goal((p.x, p.y, theta - 2 * _PI if theta >= _PI else theta))
        else:
            self.state = "forward"
            self._new_goal(self._ahead())


def _teleop(session: Session, spec: NodeSpec, node: Node) -> None:
    if not sys.stdin.isatty():
        logger.warning(
            "%s: turtle_teleop_key needs a terminal; run it in one: "
            "belvedere run turtlesim turtle_teleop_key",
            spec.source,
        )
        return
    from belvedere.teleop import TurtleKeys

    pub = node.publisher("turtle1/cmd_vel", _TWIST, queue_size=1)
    keys = TurtleKeys(
        float(node.get_param("scale_linear", 2.0)), float(node.get_param("scale_angular", 2.0))
    )

    def publish(t: tuple[float, float, float, float]) -> None:
        pub.publish_data({"linear": {"x": t[0]}, "angular": {"z": t[3]}})

    drive_from_terminal(session, node, keys, publish)  # q quits, as turtlesim's does


def _on_node(make: Callable[[Node], object]) -> Starter:
    def start(session: Session, spec: NodeSpec, node: Node) -> None:
        del session, spec
        make(node)

    return start


def _turtlesim_node(session: Session, spec: NodeSpec, node: Node) -> None:
    del spec
    # turtlesim opens its window: here, the viewer draws the canvas
    session.canvases.append(TurtlesimNode(node))
    session.want_viewer = True


EXECUTABLES: dict[str, Starter] = {
    "turtlesim_node": _turtlesim_node,
    "turtle_teleop_key": _teleop,
    "mimic": _on_node(_Mimic),
    "draw_square": _on_node(_DrawSquare),
}
NAMES = {
    "turtlesim_node": "turtlesim",
    "turtle_teleop_key": "teleop_turtle",
    "mimic": "turtle_mimic",
    "draw_square": "draw_square",
}
"""The names their ``ros::init`` gives them (``rosrun turtlesim turtlesim_node`` is
``/turtlesim``, whose ``~background_r`` the course reads as ``/turtlesim/background_r``)."""
JOINING = frozenset(EXECUTABLES)
"""Clients of the graph, as in ROS: ``run`` starts each on the graph that runs."""
