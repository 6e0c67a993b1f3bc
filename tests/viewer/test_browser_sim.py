"""The kinematic simulation in a real browser: the robot drives across the floor when /cmd_vel
says so, and the viewer's Reset button brings it back."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph, graph_running
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from belvedere.sim.physics import PhysicsSimulation
from belvedere.tf import JointStatePublisher, RobotStatePublisher
from belvedere.viewer import Viewer
from belvedere.world import read_world
from tests.conftest import EXAMPLES, free_port
from tests.viewer.docs_screenshots import docs_screenshot
from tests.viewer.test_browser import (
    RGB,
    _pixel,
    browser_page,
    driven_mbot,
    is_base_yellow,
    project,
    wait_for_pixel,
)
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.browser

BELVEDERE = [sys.executable, "-m", "belvedere"]


def test_robot_drives_in_the_viewer_and_resets() -> None:
    with driven_mbot() as mbot, browser_page(mbot.viewer.url) as page:
        cmd, base = mbot.cmd, mbot.base
        top = 0.19  # the top of the base above base_footprint
        wait_for_pixel(page, project((0.0, 0.0, top)), is_base_yellow, what="the base")
        # Backwards: away from the GUI panel on the right of the page.
        cmd.publish_data({"linear": {"x": -0.5}})
        wait_until(lambda: base.x < -0.6, what="the base past x = -0.6", detail=lambda: base.x)
        cmd.publish_data({})  # a zero Twist stops a fake ArbotiX base
        wait_until(lambda: base.dx == 0.0, what="the base to take the stop command")
        x = base.x  # the graph's thread moves it no further
        wait_for_pixel(page, project((x, 0.0, top)), is_base_yellow, what="the moved base")
        docs_screenshot(page, "arbotix")
        assert not is_base_yellow(_pixel(page, project((0.0, 0.0, top))))
        page.get_by_role("button", name="Reset").click()
        wait_until(lambda: base.x == 0.0, what="the base reset to x = 0", detail=lambda: base.x)
        wait_for_pixel(page, project((0.0, 0.0, top)), is_base_yellow, what="the reset base")


def test_physics_world_and_robot_in_the_viewer() -> None:
    """The playground's orange post and the robot's scan show in the browser."""
    packages = PackageIndex([EXAMPLES])
    world = read_world(EXAMPLES / "mbot_gazebo/worlds/playground.world", packages=packages)
    laser_bot = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_with_laser_gazebo.xacro"
    model = RobotModel.from_path(laser_bot)
    graph = Graph()
    sim = PhysicsSimulation(graph, world)
    sim.spawn(model, name="mbot", packages=packages)
    RobotStatePublisher(graph.create_node("robot_state_publisher"), model)
    JointStatePublisher(graph.create_node("joint_state_publisher"), model)
    viewer = Viewer(
        graph,
        model=model,
        port=free_port(),
        fixed_frame=sim.odom_frame,
        sim=sim,
        world=world,
        world_poses=sim.model_poses,
    )
    for kind, topic in sim.sensor_topics():
        viewer.add_display(kind, topic)
    graph.start(rtf=1.0)
    try:
        with browser_page(viewer.url) as page:

            def orange(rgb: RGB) -> bool:
                r, g, b = rgb
                return r > 150 and 0.25 * r < g < 0.8 * r and b < 60  # lit from any side

            post_2 = project((-1.0, 2.0, 0.5))
            wait_for_pixel(page, post_2, orange, what="post_2 (Gazebo/Orange)")
            wait_until(lambda: viewer.displays[0].handles, what="the scan in the viewer's scene")
            docs_screenshot(page, "gazebo_playground")
    finally:
        viewer.close()
        graph.shutdown()


def test_rosrun_rviz_beside_a_running_launch_shows_its_robot() -> None:
    """``rosrun rviz rviz -d FILE`` while the course's ArbotiX launch runs (with its own
    /rviz node) joins that launch's graph, under an anonymous name as rviz takes one: the
    launch keeps running, and the new viewer draws the launch's robot_description and its
    stamped odometry, in the launch's simulated time."""
    arbotix = EXAMPLES / "mbot_description/launch/arbotix_mbot_with_laser_xacro.launch"
    launch = [*BELVEDERE, "launch", "--headless", str(arbotix)]
    config = EXAMPLES / "mbot_description/config/mbot_arbotix.rviz"
    with subprocess.Popen(launch, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) as running:
        try:
            wait_until(
                lambda: graph_running() or running.poll() is not None, what="the launch's graph"
            )
            rviz = [
                *BELVEDERE,
                "run",
                "--port",
                str(free_port()),
                "rviz",
                "rviz",
                "-d",
                str(config),
            ]
            with subprocess.Popen(rviz, stderr=subprocess.PIPE, text=True) as viewer:
                try:
                    assert viewer.stderr is not None
                    lines = [viewer.stderr.readline() for _ in range(2)]
                    assert "connected" in lines[0], lines  # joined, no graph of its own
                    url = lines[1].removeprefix("viewer: ").strip()
                    with browser_page(url) as page:
                        page.get_by_text("✓ RobotModel (RobotModel)").wait_for()
                        page.get_by_text("✓ Odometry (Odometry)").wait_for()  # /odom, stamped
                    assert running.poll() is None, "the launch's /rviz was replaced"
                finally:
                    viewer.terminate()
                    viewer.wait(timeout=DEADLINE)
        finally:
            running.terminate()
            running.wait(timeout=DEADLINE)


def test_a_2d_nav_goal_clicked_in_the_browser_drives_move_base_there(tmp_path: Path) -> None:
    """rbx1's fake TurtleBot with move_base on the blank map: the 2D Nav Goal tool, a click
    on the floor for the position and a shift+click for the heading, and the robot drives
    there in simulated time."""
    launch = tmp_path / "fake_nav.launch"
    launch.write_text(
        "<launch>\n"
        f'  <include file="{EXAMPLES}/rbx1_bringup/launch/fake_turtlebot.launch"/>\n'
        f'  <include file="{EXAMPLES}/rbx1_nav/launch/fake_move_base_blank_map.launch"/>\n'
        "</launch>\n"
    )
    packages = PackageIndex.from_environment(near=EXAMPLES / "rbx1_nav/package.xml")
    graph = Graph()
    LaunchRuntime(load_launch(launch, packages=packages), graph, packages, headless=True).start()
    odom: list[Any] = []
    graph.create_node("probe").subscribe(
        "/odom", "nav_msgs/Odometry", lambda m: odom.append(m.pose.pose)
    )
    turtlebot = RobotModel.from_path(EXAMPLES / "rbx1_description/urdf/turtlebot.urdf.xacro")
    viewer = Viewer(graph, model=turtlebot, port=free_port(), fixed_frame="map")
    viewer.add_display("Map", "/map")  # as the course's rviz shows navigation
    viewer.add_display("Path", "/move_base/NavfnROS/plan")
    graph.start(rtf=4.0)
    target, towards = (-0.3, -0.8), (-0.3, -0.3)  # facing +y: a quarter turn from the start

    def arrived() -> bool:
        if not odom:
            return False
        p, q = odom[-1].position, odom[-1].orientation
        yaw = 2 * math.atan2(q.z, q.w)
        return (
            math.hypot(p.x - target[0], p.y - target[1]) < 0.15
            and abs(math.remainder(yaw - math.pi / 2, math.tau)) < 0.15
        )

    try:
        with browser_page(viewer.url) as page:
            page.get_by_role("button", name="2D Nav Goal").click()
            wait_until(lambda: viewer.tool == "goal", what="the 2D Nav Goal tool chosen")
            page.mouse.click(*project((*target, 0.0)))
            page.keyboard.down("Shift")
            page.mouse.click(*project((*towards, 0.0)))
            page.keyboard.up("Shift")
            wait_until(
                arrived,
                what="the robot at the clicked goal, facing the shift+click",
                detail=lambda: odom[-1] if odom else None,
            )
            docs_screenshot(page, "nav_goal")
    finally:
        viewer.close()
        graph.shutdown()
