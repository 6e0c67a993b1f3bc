"""Cameras lit like Gazebo's: the scene's ambient light and background, the sun, materials'
ambient and diffuse colours, no headlight; image formats; rendering only for listeners."""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from belvedere.description.urdf import Pose, RobotModel
from belvedere.graph import Graph
from belvedere.sim.physics import CameraSensor, PhysicsSimulation
from belvedere.world import read_world_string

CAMERA_ROBOT = """<robot name="eye">
  <link name="base"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <gazebo reference="base">
    <sensor type="camera" name="eye_camera">
      <update_rate>10</update_rate>
      <camera><horizontal_fov>1.0</horizontal_fov>
        <image><width>160</width><height>120</height><format>{format}</format></image>
        <clip><near>0.02</near><far>100</far></clip></camera>
      <plugin name="eye_plugin" filename="libgazebo_ros_camera.so">
        <cameraName>eye</cameraName><frameName>base</frameName></plugin>
    </sensor>
  </gazebo>
</robot>"""

RED_BOX_WORLD = """<sdf version="1.6"><world name="default">
  <include><uri>model://ground_plane</uri></include>
  <include><uri>model://sun</uri></include>
  {scene}
  <model name="red_box"><static>true</static><pose>2 0 0.5 0 0 0</pose>
    <link name="link"><visual name="visual"><geometry><box><size>1 1 1</size></box></geometry>
      <material>{material}</material></visual></link></model>
</world></sdf>"""

SUN_DIRECTION = np.array([-0.5, 0.1, -0.9])
"""model://sun's <direction>."""


def _camera_world(world_text: str, *, fmt: str = "R8G8B8") -> tuple[Graph, Any]:
    graph = Graph()
    sim = PhysicsSimulation(graph, read_world_string(world_text, "world.sdf"))
    robot = RobotModel.from_string(CAMERA_ROBOT.format(format=fmt), path="eye.urdf")
    # Hovering at x = 4 (gravity off), looking back along -x at the box's +x face, which the
    # sun lights at n·l = 0.5 / |direction|.
    sim.spawn(robot, pose=Pose((4.0, 0.0, 0.5), (0.0, 0.0, math.pi)))
    sim.engine.m.body_gravcomp[:] = 1.0
    return graph, sim


def _last_image(graph: Graph, seconds: float = 0.15) -> Any:
    images: list[Any] = []
    graph.create_node("probe").subscribe("/eye/image_raw", "sensor_msgs/Image", images.append)
    graph.run(duration=seconds)
    assert images, "no image (is EGL rendering available?)"
    return images[-1]


def _phong(ambient: float, diffuse: float, scene_ambient: float = 0.4) -> float:
    """Gazebo's (OGRE's) Lambert + ambient shading of the box's +x face under the sun."""
    cos = float(SUN_DIRECTION @ np.array([-1.0, 0.0, 0.0]) / np.linalg.norm(SUN_DIRECTION))
    return 255 * (ambient * scene_ambient + diffuse * 0.8 * max(cos, 0.0))


def _red_face(image: Any) -> npt.NDArray[np.float64]:
    pixels = np.asarray(image.data).reshape(image.height, image.width, 3).astype(float)
    red = (pixels[:, :, 0] > pixels[:, :, 1] + 40) & (pixels[:, :, 1] < 10)
    assert red.sum() > 0.1 * red.size, "the box fills a good part of the view"
    mean: npt.NDArray[np.float64] = pixels[red].mean(axis=0)
    return mean


def test_red_box_under_the_sun_is_phong_shaded_and_the_sky_is_the_background() -> None:
    world = RED_BOX_WORLD.format(
        scene="", material="<ambient>1 0 0 1</ambient><diffuse>1 0 0 1</diffuse>"
    )
    graph, _ = _camera_world(world)
    image = _last_image(graph)
    r, g, b = _red_face(image)
    assert r == pytest.approx(_phong(1.0, 1.0), rel=0.10)
    assert (g, b) == (0.0, 0.0)
    pixels = np.asarray(image.data).reshape(image.height, image.width, 3)
    assert tuple(pixels[0, 0]) == (178, 178, 178)  # Gazebo's default background, 0.7 grey
    assert tuple(pixels[0, -1]) == (178, 178, 178)


def test_scene_ambient_background_and_material_ambient_are_used() -> None:
    scene = "<scene><ambient>0.2 0.2 0.2 1</ambient><background>0.1 0.3 0.5 1</background></scene>"
    world = RED_BOX_WORLD.format(
        scene=scene, material="<ambient>0.5 0 0 1</ambient><diffuse>0.8 0 0 1</diffuse>"
    )
    graph, _ = _camera_world(world)
    image = _last_image(graph)
    r, _, _ = _red_face(image)
    assert r == pytest.approx(_phong(0.5, 0.8, scene_ambient=0.2), rel=0.10)
    pixels = np.asarray(image.data).reshape(image.height, image.width, 3)
    assert np.abs(pixels[0, 0].astype(int) - [25.5, 76.5, 127.5]).max() <= 1


def test_gazebo_named_material_and_ground_plane() -> None:
    world = RED_BOX_WORLD.format(scene="", material="<script><name>Gazebo/Red</name></script>")
    graph, _ = _camera_world(world)
    image = _last_image(graph)
    r, _, _ = _red_face(image)
    assert r == pytest.approx(_phong(1.0, 1.0), rel=0.10)  # plus a faint specular
    pixels = np.asarray(image.data).reshape(image.height, image.width, 3)
    ground = pixels[-1, 0].astype(float)  # Gazebo/Grey: ambient 0.3, diffuse 0.7, sun from above
    cos = 0.9 / float(np.linalg.norm(SUN_DIRECTION))
    assert ground[0] == pytest.approx(255 * (0.3 * 0.4 + 0.7 * 0.8 * cos), rel=0.10)


def test_a_point_light_lights_what_the_sun_does_not() -> None:
    lamp = """<light name="lamp" type="point"><pose>3 0 0.5 0 0 0</pose>
      <diffuse>1 1 1 1</diffuse><specular>0 0 0 1</specular>
      <attenuation><range>20</range><constant>1</constant><linear>0</linear>
      <quadratic>0</quadratic></attenuation></light>"""
    world = RED_BOX_WORLD.format(scene=lamp, material="<diffuse>1 0 0 1</diffuse>")
    graph, _ = _camera_world(world.replace("<include><uri>model://sun</uri></include>", ""))
    r, _, _ = _red_face(_last_image(graph))
    # The lamp faces the +x face at 0.5 m: n·l near 1 at the centre, less towards the edges.
    assert 0.4 * 255 + 0.5 * 255 < r <= 255


def test_unknown_image_format_is_one_warning_and_rgb8(caplog: pytest.LogCaptureFixture) -> None:
    world = RED_BOX_WORLD.format(scene="", material="<diffuse>1 0 0 1</diffuse>")
    with caplog.at_level(logging.WARNING, logger="belvedere"):
        graph, _ = _camera_world(world, fmt="RGB8B8")
    warnings = [r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING]
    assert len(warnings) == 1, warnings
    assert "eye.urdf:8:" in warnings[0]  # the <format> element
    assert "'RGB8B8'" in warnings[0]
    assert "R8G8B8" in warnings[0]
    assert _last_image(graph).encoding == "rgb8"


@pytest.mark.parametrize(
    ("fmt", "encoding", "step"),
    [
        ("L8", "mono8", 160),
        ("B8G8R8", "bgr8", 480),
        ("L16", "mono16", 320),
        ("BAYER_RGGB8", "bayer_rggb8", 160),
    ],
)
def test_image_formats(fmt: str, encoding: str, step: int) -> None:
    world = RED_BOX_WORLD.format(scene="", material="<diffuse>1 0 0 1</diffuse>")
    graph, _ = _camera_world(world, fmt=fmt)
    image = _last_image(graph)
    assert (image.encoding, image.step, len(image.data)) == (encoding, step, step * 120)
    if encoding == "bayer_rggb8":
        pixels = np.asarray(image.data).reshape(120, 160)
        assert pixels[60, 80] > 150  # a red pixel
        assert pixels[61, 81] == 0  # a blue one


def test_a_camera_nobody_listens_to_renders_nothing() -> None:
    world = RED_BOX_WORLD.format(scene="", material="<diffuse>1 0 0 1</diffuse>")
    graph, sim = _camera_world(world)
    camera = next(p for p in sim.plugins if isinstance(p, CameraSensor))
    graph.run(duration=0.5)
    assert camera.renderer.frames == 0
    images: list[Any] = []
    sub = graph.create_node("probe").subscribe("/eye/image_raw", "sensor_msgs/Image", images.append)
    graph.run(duration=0.5)
    assert camera.renderer.frames == len(images) == 5  # 10 Hz
    sub.unregister()
    graph.run(duration=0.5)
    assert camera.renderer.frames == 5
