"""The kinematic simulation in a real browser: the robot drives across the floor when /cmd_vel
says so, and the viewer's Reset button brings it back."""

from __future__ import annotations

import subprocess
import sys

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph, graph_running
from belvedere.packages import PackageIndex
from belvedere.sim.kinematic import KinematicSimulation
from belvedere.sim.physics import PhysicsSimulation
from belvedere.tf import JointStatePublisher, RobotStatePublisher
from belvedere.viewer import Viewer
from belvedere.world import read_world
from tests.conftest import EXAMPLES
from tests.viewer.test_browser import (
    MBOT,
    RGB,
    _free_port,
    _pixel,
    browser_page,
    is_base_yellow,
    project,
    wait_for_pixel,
)
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.browser

BELVEDERE = [sys.executable, "-m", "belvedere"]


def test_robot_drives_in_the_viewer_and_resets() -> None:
    model = RobotModel.from_path(MBOT)
    graph = Graph()
    sim = KinematicSimulation(graph, model)
    viewer = Viewer(graph, model=model, port=_free_port(), fixed_frame=sim.odom_frame, sim=sim)
    cmd = graph.create_node("driver").publisher("/cmd_vel", "geometry_msgs/Twist")
    graph.start(rtf=1.0)
    base = sim.driver.base
    assert base is not None
    try:
        with browser_page(viewer.url) as page:
            top = 0.19  # the top of the base above base_footprint
            wait_for_pixel(page, project((0.0, 0.0, top)), is_base_yellow, what="the base")
            # Backwards: away from the GUI panel on the right of the page.
            cmd.publish_data({"linear": {"x": -0.5}})
            wait_until(lambda: base.x < -0.6, what="the base past x = -0.6", detail=lambda: base.x)
            cmd.publish_data({})  # a zero Twist stops a fake ArbotiX base
            wait_until(lambda: base.dx == 0.0, what="the base to take the stop command")
            x = base.x  # the graph's thread moves it no further
            wait_for_pixel(page, project((x, 0.0, top)), is_base_yellow, what="the moved base")
            assert not is_base_yellow(_pixel(page, project((0.0, 0.0, top))))
            page.get_by_role("button", name="Reset").click()
            wait_until(lambda: base.x == 0.0, what="the base reset to x = 0", detail=lambda: base.x)
            wait_for_pixel(page, project((0.0, 0.0, top)), is_base_yellow, what="the reset base")
    finally:
        viewer.close()
        graph.shutdown()


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
        port=_free_port(),
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
                str(_free_port()),
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
