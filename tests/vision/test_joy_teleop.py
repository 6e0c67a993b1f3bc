"""Joysticks' teleop nodes: turtlebot_teleop_joy as turtlebot's logitech.launch configures
it drives a simulated turtle while the deadman button is held and stops it when let go;
teleop_twist_joy's enable, turbo and axis maps; a bad parameter is one error."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.errors import ParseError
from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.msgs import build, types
from belvedere.packages import PackageIndex


def _joy(axes: list[float], buttons: list[int]) -> Any:
    joy = types().cls("sensor_msgs/Joy")
    return joy(build.header(0), np.array(axes, np.float32), np.array(buttons, np.int32))


def _started(tmp_path: Path, body: str) -> Graph:
    launch = tmp_path / "joy.launch"
    launch.write_text(f"<launch>\n{body}\n</launch>")
    packages = PackageIndex([])
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    return graph


LOGITECH = """\
<node pkg="turtlesim" type="turtlesim_node" name="sim"/>
<node pkg="turtlebot_teleop" type="turtlebot_teleop_joy" name="turtlebot_teleop_joystick">
  <param name="scale_angular" value="1.5"/>
  <param name="scale_linear" value="0.5"/>
  <param name="axis_deadman" value="10"/>
  <param name="axis_linear" value="1"/>
  <param name="axis_angular" value="0"/>
  <remap from="turtlebot_teleop_joystick/cmd_vel" to="/turtle1/cmd_vel"/>
</node>"""


def test_logitech_launch_drives_the_turtle_while_the_deadman_is_held(tmp_path: Path) -> None:
    graph = _started(tmp_path, LOGITECH)
    poses: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/turtle1/pose", "turtlesim/Pose", poses.append, queue_size=1000)
    joy = probe.publisher("/joy", "sensor_msgs/Joy")
    graph.run(duration=0.2)
    start = poses[-1]
    buttons = [0] * 11
    buttons[10] = 1
    joy.publish(_joy([0.0, 1.0], buttons))  # full ahead, deadman held
    graph.run(duration=1.0)
    moved = poses[-1]
    assert moved.x - start.x == pytest.approx(0.5 * 0.9, abs=0.1)  # 0.5 m/s for ~0.9 s
    assert moved.linear_velocity == pytest.approx(0.5)
    joy.publish(_joy([0.0, 1.0], [0] * 11))  # let go: one stop
    graph.run(duration=1.0)
    assert poses[-1].x == pytest.approx(poses[-5].x)
    assert poses[-1].x - moved.x < 0.1


def test_teleop_twist_joy_enable_turbo_and_axis_maps(tmp_path: Path) -> None:
    graph = _started(
        tmp_path,
        """<node pkg="teleop_twist_joy" type="teleop_node" name="teleop">
             <param name="enable_button" value="4"/>
             <param name="enable_turbo_button" value="5"/>
             <rosparam param="axis_linear">{x: 1, y: 2}</rosparam>
             <rosparam param="scale_linear">{x: 0.7, y: 0.3}</rosparam>
             <rosparam param="scale_linear_turbo">{x: 1.5, y: 0.6}</rosparam>
             <param name="axis_angular" value="0"/>
             <param name="scale_angular" value="0.4"/>
           </node>""",
    )
    twists: list[Any] = []
    probe = graph.create_node("probe")
    probe.subscribe("/cmd_vel", "geometry_msgs/Twist", twists.append, queue_size=100)
    joy = probe.publisher("/joy", "sensor_msgs/Joy")
    graph.run(duration=0.05)
    for buttons in ([0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1], [0] * 6, [0] * 6):
        joy.publish(_joy([0.5, 1.0, -1.0], buttons))
        graph.run(duration=0.05)
    said = [v for t in twists for v in (t.linear.x, t.linear.y, t.angular.z)]
    # enabled; turbo (its yaw scale the default 1.0); let go: one stop, then nothing
    assert said == pytest.approx([0.7, -0.3, 0.2, 1.5, -0.6, 0.5, 0.0, 0.0, 0.0])


def test_a_bad_teleop_parameter_is_one_error(tmp_path: Path) -> None:
    with pytest.raises(
        ParseError, match=r"joy.launch:2.*parameter ~axis_deadman: expected an axis"
    ):
        _started(
            tmp_path,
            """<node pkg="turtlebot_teleop" type="turtlebot_teleop_joy" name="t">
                 <param name="axis_deadman" value="left"/></node>""",
        )
