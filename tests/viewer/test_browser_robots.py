"""Many robots in the viewer (mbot_gazebo multi_mbot.launch with its multi_mbot.rviz): one
RobotModel per robot (``robot_i/robot_description``, TF prefix ``robot_i``) draws every
robot where it is in the world frame, and one that drives is drawn where it went."""

from __future__ import annotations

import math
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from belvedere.viewer import Viewer, read_rviz
from tests.conftest import EXAMPLES, free_port
from tests.viewer.test_browser import BROWSER_DEADLINE, browser_page, view_centre, wait_for_pixel
from tests.viewer.test_browser_displays import is_base
from tests.waiting import wait_until

pytestmark = pytest.mark.browser

LAUNCH = EXAMPLES / "mbot_gazebo/launch/multi_mbot.launch"
RVIZ = EXAMPLES / "mbot_gazebo/config/multi_mbot.rviz"
SCALE = 70.0
"""multi_mbot.rviz's TopDownOrtho pixels per metre."""
START = {"robot_1": (0.0, 0.0), "robot_2": (0.0, 1.5), "robot_3": (0.0, -1.5)}
ON_BASE = (-0.12, 0.0)
"""A point of the yellow base seen from above, beside the black laser on its middle."""


def _pixel(x: float, y: float) -> tuple[float, float]:
    cx, cy = view_centre()
    return (cx + x * SCALE, cy - y * SCALE)


def _not_base(rgb: tuple[int, int, int]) -> bool:
    return not is_base(rgb)


def test_every_robot_is_drawn_where_it_is() -> None:
    packages = PackageIndex([EXAMPLES])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(LAUNCH, packages=packages), graph, packages, headless=True)
    runtime.start()
    viewer = Viewer(graph, port=free_port(), rviz=read_rviz(RVIZ), packages=packages)
    probe = graph.create_node("probe")
    odom: list[Any] = []
    probe.subscribe("/robot_2/odom", "nav_msgs/Odometry", odom.append, queue_size=1)
    cmd = probe.publisher("/robot_2/cmd_vel", "geometry_msgs/Twist")
    graph.start(rtf=1.0)
    try:
        with browser_page(viewer.url) as page:
            for robot, (x, y) in START.items():
                at = _pixel(x + ON_BASE[0], y + ON_BASE[1])
                wait_for_pixel(page, at, is_base, what=f"{robot}'s base")
            between = _pixel(ON_BASE[0], 0.75)
            wait_for_pixel(page, between, _not_base, what="no robot between robot_1 and 2")
            graph.executor.post(lambda: cmd.publish_data({"linear": {"x": 0.5}}))
            wait_until(
                lambda: odom and odom[-1].pose.pose.position.x > 0.6,
                what="robot_2 past x = 0.6",
                detail=lambda: odom[-1].pose.pose.position.x if odom else None,
                timeout=BROWSER_DEADLINE,
            )
            graph.executor.post(lambda: cmd.publish_data({}))
            wait_until(
                lambda: abs(odom[-1].twist.twist.linear.x) < 0.01,
                what="robot_2 to stop",
                timeout=BROWSER_DEADLINE,
            )
            pose = odom[-1].pose.pose
            q = pose.orientation
            yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
            x2 = pose.position.x + ON_BASE[0] * math.cos(yaw)
            y2 = pose.position.y + ON_BASE[0] * math.sin(yaw)
            wait_for_pixel(page, _pixel(x2, y2), is_base, what="robot_2 where it drove")
            wait_for_pixel(
                page, _pixel(ON_BASE[0], 1.5), _not_base, what="robot_2 gone from its start"
            )
            wait_for_pixel(
                page, _pixel(ON_BASE[0], -1.5), is_base, what="robot_3 still at its start"
            )
    finally:
        viewer.close()
        runtime.close()
        graph.shutdown()
