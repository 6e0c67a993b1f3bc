"""``belvedere tf echo SOURCE TARGET`` and ``belvedere tf tree``."""

from __future__ import annotations

import argparse
import math
import sys
import time

from belvedere.cli._tool import action_parsers, graph_address
from belvedere.errors import BelvedereError
from belvedere.graph import NS
from belvedere.runtime import open_tool, wait_for
from belvedere.tf import TFBuffer, TFError, TransformListener, rpy_from_quat_xyzw

__all__ = ["add_parser", "run"]


def add_parser(
    sub: argparse._SubParsersAction[argparse.ArgumentParser], common: argparse.ArgumentParser
) -> None:
    p = sub.add_parser("tf", parents=[common], help="transforms: echo one, or show the tree")
    verb = action_parsers(p, common)
    v = verb("echo", "print TARGET's pose in SOURCE (tf_echo)")
    v.add_argument("source", help="the frame to express… (tf_echo's first argument)")
    v.add_argument("target", help="…in this frame")
    v.add_argument("-n", dest="count", type=int, help="stop after COUNT prints (one a second)")
    v.add_argument("--timeout", type=float, default=5.0, help="give up after SECONDS")
    v = verb("tree", "the frame tree with rates (view_frames)")
    v.add_argument("--wait", type=float, default=2.0, help="listen for SECONDS first")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    tool = open_tool(graph_address(args), "tf")
    try:
        buffer = TFBuffer()
        TransformListener(tool.node, buffer)
        clock: list[int] = []  # a simulation's time: the transforms' stamps are in it
        tool.node.subscribe(
            "/clock",
            "rosgraph_msgs/Clock",
            lambda m: clock.append(m.clock.sec * NS + m.clock.nanosec),
            queue_size=1,
        )
        tool.graph.start(rtf=None)
        if args.action == "tree":
            time.sleep(args.wait)
            tree = buffer.tree(now_ns=clock[-1] if clock else time.time_ns())
            if not tree:
                msg = f"no transforms on /tf or /tf_static within {args.wait:g} s"
                raise BelvedereError(msg)
            sys.stdout.write(tree + "\n")
            return 0
        # tf_echo SOURCE TARGET prints the transform from SOURCE to TARGET: TARGET's pose
        # expressed in SOURCE.
        if not wait_for(lambda: buffer.can_transform(args.source, args.target), args.timeout):
            try:
                buffer.lookup_transform(args.source, args.target)
            except TFError as err:
                within = f"within {args.timeout:g} s"
                msg = f"no transform {args.source} -> {args.target} {within}: {err.message}"
                raise BelvedereError(msg.rstrip(), hint=err.hint) from None
        printed = 0
        while args.count is None or printed < args.count:
            t = buffer.lookup_transform(args.source, args.target)
            x, y, z = t.translation
            qx, qy, qz, qw = t.quat_xyzw
            r, p, yaw = rpy_from_quat_xyzw(t.quat_xyzw)
            sys.stdout.write(
                f"- Translation: [{x:.3f}, {y:.3f}, {z:.3f}]\n"
                f"- Rotation: in Quaternion [{qx:.3f}, {qy:.3f}, {qz:.3f}, {qw:.3f}]\n"
                f"            in RPY (radian) [{r:.3f}, {p:.3f}, {yaw:.3f}]\n"
                f"            in RPY (degree) [{math.degrees(r):.3f}, {math.degrees(p):.3f}, "
                f"{math.degrees(yaw):.3f}]\n"
            )
            sys.stdout.flush()
            printed += 1
            if args.count is None or printed < args.count:
                time.sleep(1.0)
        return 0
    except KeyboardInterrupt:
        if tool.ended_by is None:
            raise
        return 0  # node kill: tf_echo's loop ends with its node
    finally:
        tool.close()
