"""The course's navigation, end to end: the physics simulation of the cloister with the
course-style nav_cloister_demo.launch (map_server + amcl + move_base on the map belvedere made)
drives the robot to a 2D Nav Goal and localizes it; on rbx1's fake path, a rospy script sends
move_base goals through actionlib, as the book's demos do."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

from belvedere.graph import Graph
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE

BELVEDERE = [sys.executable, "-m", "belvedere"]


def test_a_nav_goal_in_the_cloister(tmp_path: Path) -> None:
    launch = tmp_path / "nav.launch"
    launch.write_text(
        "<launch>\n"
        f'  <include file="{EXAMPLES}/mbot_gazebo/launch/mbot_laser_nav_gazebo.launch"/>\n'
        f'  <include file="{EXAMPLES}/mbot_navigation/launch/nav_cloister_demo.launch"/>\n'
        "</launch>\n"
    )
    packages = PackageIndex.from_environment(near=EXAMPLES / "mbot_navigation/package.xml")
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    probe = graph.create_node("probe")
    odom: list[Any] = []
    amcl: list[Any] = []
    clouds: list[Any] = []
    probe.subscribe("/odom", "nav_msgs/Odometry", lambda m: odom.append(m.pose.pose))
    probe.subscribe(
        "/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", lambda m: amcl.append(m)
    )
    probe.subscribe("/particlecloud", "geometry_msgs/PoseArray", clouds.append)
    goal = probe.publisher("/move_base_simple/goal", "geometry_msgs/PoseStamped")
    try:
        graph.run(duration=2.0)
        # the viewer's 2D Nav Goal: the east walk, facing north
        goal.publish_data(
            {
                "header": {"frame_id": "map"},
                "pose": {
                    "position": {"x": 5.5, "y": 0.0},
                    "orientation": {"z": 0.7071, "w": 0.7071},
                },
            }
        )

        def there() -> bool:
            return bool(odom) and math.hypot(odom[-1].position.x - 5.5, odom[-1].position.y) < 0.15

        graph.run(duration=90.0, until=there)
        graph.run(duration=2.0)
    finally:
        graph.shutdown()
    end = odom[-1]  # the simulation's odometry is the true pose (map = world here)
    assert math.hypot(end.position.x - 5.5, end.position.y) < 0.15
    assert amcl  # amcl updated as the robot moved
    estimate = amcl[-1].pose.pose.position
    assert math.hypot(estimate.x - end.position.x, estimate.y - end.position.y) < 0.15
    assert amcl[-1].header.frame_id == "map"
    assert clouds
    assert len(clouds[-1].poses) >= 500  # min_particles of the course's amcl.launch


def test_a_rospy_script_sends_actionlib_goals(tmp_path: Path) -> None:
    launch = tmp_path / "fake_nav_goals.launch"
    launch.write_text(
        "<launch>\n"
        f'  <include file="{EXAMPLES}/rbx1_bringup/launch/fake_turtlebot.launch"/>\n'
        f'  <include file="{EXAMPLES}/rbx1_nav/launch/fake_move_base_blank_map.launch"/>\n'
        '  <node pkg="rbx1_nav" type="nav_goals.py" name="nav_goals" output="screen"\n'
        '        required="true">\n'
        '    <rosparam param="goals">[[1.0, 0.0, 0.0], [1.0, 1.0, 1.57]]</rosparam>\n'
        "  </node>\n"
        "</launch>\n"
    )
    proc = subprocess.run(
        [*BELVEDERE, "launch", "--package-path", str(EXAMPLES), str(launch), "--headless"],
        capture_output=True,
        text=True,
        timeout=DEADLINE * 3,
        check=False,
    )
    out = proc.stdout + proc.stderr
    assert "Goal ended: SUCCEEDED" in out, out[-2000:]
    assert "Reached 2 of 2 goals" in out, out[-2000:]


def test_exploring_while_mapping_in_the_cloister(tmp_path: Path) -> None:
    """The course's exploring_slam demo: the physics cloister, gmapping and move_base on its
    growing map, and a rospy script sending actionlib goals along the south walk."""
    launch = tmp_path / "exploring.launch"
    launch.write_text(
        "<launch>\n"
        f'  <include file="{EXAMPLES}/mbot_gazebo/launch/mbot_laser_nav_gazebo.launch">\n'
        '    <arg name="gui" value="false"/>\n'
        "  </include>\n"
        f'  <include file="{EXAMPLES}/mbot_navigation/launch/exploring_slam_demo.launch"/>\n'
        '  <node pkg="mbot_navigation" type="exploring_slam.py" name="exploring_slam"\n'
        '        output="screen" required="true"/>\n'
        "</launch>\n"
    )
    proc = subprocess.run(
        [*BELVEDERE, "launch", "--package-path", str(EXAMPLES), str(launch), "--headless"],
        capture_output=True,
        text=True,
        timeout=DEADLINE * 6,
        check=False,
    )
    out = proc.stdout + proc.stderr
    assert "Reached 2 of 2 goals" in out, out[-3000:]
    areas = [float(a) for a in re.findall(r"the map knows ([0-9.]+) m\^2", out)]
    assert len(areas) == 2, out[-3000:]
    # the map grew on the way from the first goal to the second
    assert 0 < areas[0] < areas[1], areas
