"""``belvedere teleop``: drive a robot from the keyboard (teleop_twist_keyboard, or the
course's mbot_teleop with ``--layout mbot``)."""

from __future__ import annotations

import argparse
import signal
import sys
import threading
from types import FrameType

from belvedere.cli._tool import add_graph_options, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import parse_ros_args
from belvedere.msgs import types
from belvedere.runtime import open_tool, wait_for
from belvedere.teleop import LAYOUTS, Layout, MbotTeleop, TwistKeyboard, run_teleop

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser(
        "teleop",
        parents=[common],
        help="drive a robot from the keyboard",
        description="Publish geometry_msgs/Twist from key presses, as teleop_twist_keyboard "
        "does. ROS-style arguments work too: _speed:=0.3 _turn:=0.8 cmd_vel:=/robot/cmd_vel.",
    )
    p.add_argument("--topic", default="cmd_vel", help="the Twist topic (default: cmd_vel)")
    p.add_argument("--layout", choices=sorted(LAYOUTS), default="twist_keyboard")
    p.add_argument("--speed", type=float, help="linear speed (default 0.5; mbot 0.2)")
    p.add_argument("--turn", type=float, help="angular speed (default 1.0)")
    p.add_argument(
        "--repeat-rate",
        type=float,
        default=0.0,
        metavar="HZ",
        help="republish the current command at HZ (default: only on key presses)",
    )
    p.add_argument(
        "--key-timeout",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="stop when no key comes for SECONDS (twist_keyboard; default: never)",
    )
    add_graph_options(p)
    p.set_defaults(run=run)


def _number(params: dict[str, object], name: str, given: float | None) -> float | None:
    """A ``_name:=value`` parameter (winning over the option) as a float."""
    value = params.get(name, given)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float):
        msg = f"_{name} must be a number, got {value!r}"
        raise BelvedereError(msg)
    return float(value)


def _layout(args: argparse.Namespace, params: dict[str, object]) -> Layout:
    speed, turn = _number(params, "speed", args.speed), _number(params, "turn", args.turn)
    timeout = _number(params, "key_timeout", args.key_timeout) or 0.0
    if args.layout == "mbot":
        return MbotTeleop(speed=0.2 if speed is None else speed, turn=turn or 1.0)
    return TwistKeyboard(
        speed=0.5 if speed is None else speed,
        turn=1.0 if turn is None else turn,
        key_timeout=timeout,
    )


def run(args: argparse.Namespace) -> int:
    ros = parse_ros_args(args.extra)
    if ros.rest:
        msg = f"unexpected arguments: {' '.join(ros.rest)}"
        raise BelvedereError(msg)
    layout = _layout(args, ros.params)
    rate = _number(ros.params, "repeat_rate", args.repeat_rate) or 0.0
    tool = open_tool(graph_address(args), "teleop")
    try:
        topic = tool.node.resolve(ros.remappings.get(args.topic, args.topic))
        pub = tool.node.publisher(topic, "geometry_msgs/Twist", queue_size=1)
        tool.graph.start(rtf=None)
        wait_for(lambda: pub.topic.remote, 1.0)  # let subscribers elsewhere see us first
        twist_type = types().cls("geometry_msgs/Twist")
        vector = types().cls("geometry_msgs/Vector3")
        current = [(0.0, 0.0, 0.0, 0.0)]

        def publish(twist: tuple[float, float, float, float]) -> None:
            current[0] = twist
            x, y, z, th = twist
            pub.publish(twist_type(vector(x, y, z), vector(0.0, 0.0, th)))

        stop = threading.Event()
        if rate > 0:

            def repeat() -> None:
                while not stop.wait(1.0 / rate):
                    publish(current[0])

            threading.Thread(target=repeat, daemon=True).start()

        def on_term(signum: int, frame: FrameType | None) -> None:
            raise SystemExit(0)

        signal.signal(signal.SIGTERM, on_term)
        try:
            run_teleop(layout, publish, sys.stdin.fileno(), sys.stdout)
        finally:
            stop.set()
        wait_for(lambda: False, 0.2)  # let the last (zero) Twist leave
        return 0
    finally:
        tool.close()
