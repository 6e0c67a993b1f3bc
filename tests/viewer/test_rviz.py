"""``.rviz`` configs: read as rviz 1.14 reads them, written so that Debian's rviz opens them."""

from __future__ import annotations

import math
import os
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import pytest

from belvedere.errors import BelvedereError, ParseError
from belvedere.fileio import FileWriteError
from belvedere.viewer import read_rviz
from belvedere.viewer._rviz import (
    DEFAULTS,
    VIEW_DEFAULTS,
    RvizConfig,
    RvizDisplay,
    RvizView,
    format_color,
    parse_color,
    write_rviz,
)
from tests.conftest import EXAMPLES
from tests.tf.ros1 import Roscore, start_roscore
from tests.viewer.rviz_oracle import missing_rviz, open_in_rviz

# Every display class the course's and rbx1's configs use, each with values that are not
# rviz's defaults (so a value that is dropped or renamed shows). The Image and Camera displays
# are on: rviz switches a display with a panel on when it opens a config without its binary
# window state (rviz issue #914's "fresh config" case), which a written config never has.
EVERY_CLASS = """\
Panels:
  - Class: rviz/Displays
    Name: Displays
    Property Tree Widget:
      Expanded: [/Global Options1]
Visualization Manager:
  Class: ""
  Displays:
    - Class: rviz/Grid
      Name: Floor
      Enabled: true
      Cell Size: 0.5
      Plane Cell Count: 20
      Color: 100; 100; 100
      Alpha: 0.25
      Line Style:
        Line Width: 0.05
        Value: Billboards
      Reference Frame: odom
    - Class: rviz/RobotModel
      Name: Robot
      Enabled: true
      Alpha: 0.5
      Visual Enabled: false
      Collision Enabled: true
      Robot Description: mbot_description
    - Class: rviz/TF
      Name: TF
      Enabled: true
      Show Names: false
      Show Axes: true
      Show Arrows: false
      Marker Scale: 0.5
      Frame Timeout: 5
      Frames:
        All Enabled: false
        base_link:
          Value: true
    - Class: rviz/LaserScan
      Name: Scan
      Enabled: true
      Topic: /scan
      Size (m): 0.05
      Decay Time: 2
      Style: Points
      Alpha: 0.8
      Queue Size: 5
      Color: 255; 0; 0
      Color Transformer: FlatColor
    - Class: rviz/PointCloud2
      Name: Cloud
      Enabled: false
      Topic: /camera/depth/points
      Size (m): 0.02
      Style: Spheres
      Decay Time: 1.5
    - Class: rviz/Map
      Name: Map
      Enabled: true
      Topic: /map
      Alpha: 0.6
      Color Scheme: map
      Draw Behind: true
    - Class: rviz/Map
      Name: Local Costmap
      Enabled: true
      Topic: /move_base/local_costmap/costmap
      Alpha: 0.4
      Color Scheme: costmap
    - Class: rviz/Path
      Name: Global Plan
      Enabled: true
      Topic: /move_base/NavfnROS/plan
      Color: 0; 12; 255
      Line Style: Billboards
      Line Width: 0.05
      Buffer Length: 3
    - Class: rviz/PoseArray
      Name: ParticleCloud
      Enabled: true
      Topic: /particlecloud
      Color: 255; 0; 255
      Arrow Length: 0.5
      Shape: Arrow (3D)
    - Class: rviz/Odometry
      Name: Odometry
      Enabled: true
      Topic: /odom
      Keep: 20
      Position Tolerance: 0.2
      Angle Tolerance: 0.3
      Shape:
        Value: Axes
        Color: 221; 200; 14
        Axes Length: 0.5
    - Class: rviz/Image
      Name: Image
      Enabled: true
      Image Topic: /camera/rgb/image_raw
      Queue Size: 3
    - Class: rviz/Camera
      Name: Camera
      Enabled: true
      Image Topic: /camera/rgb/image_raw
      Overlay Alpha: 0.7
      Zoom Factor: 2
    - Class: rviz/Marker
      Name: Waypoints
      Enabled: true
      Marker Topic: /waypoint_markers
      Queue Size: 50
      Namespaces:
        {}
    - Class: rviz/MarkerArray
      Name: MarkerArray
      Enabled: true
    - Class: rviz/Polygon
      Name: Footprint
      Enabled: true
      Topic: /move_base/local_costmap/footprint
      Color: 0; 255; 0
      Alpha: 0.5
    - Class: rviz/Pose
      Name: Goal
      Enabled: true
      Topic: /move_base/current_goal
      Color: 0; 255; 0
      Shape: Axes
      Axes Length: 0.7
    - Class: rviz/InteractiveMarkers
      Name: Interact
      Enabled: false
      Update Topic: /basic_controls/update
      Show Axes: true
      Show Descriptions: false
    - Class: rviz/Group
      Name: Sensors
      Enabled: true
      Displays:
        - Class: rviz/Axes
          Name: Laser Axes
          Enabled: true
          Reference Frame: laser_link
          Length: 0.3
          Radius: 0.02
        - Class: rviz/PointStamped
          Name: Clicked
          Enabled: false
          Topic: /clicked_point
          Color: 255; 255; 0
          Radius: 0.1
          History Length: 5
    - Class: rviz/GridCells
      Name: Inflated Obstacles
      Enabled: true
      Topic: /move_base/global_costmap/inflated_obstacles
      Color: 38; 190; 255
    - Class: rviz/PointCloud
      Name: Old Cloud
      Enabled: false
      Topic: /cloud
      Style: Boxes
    - Class: rviz/PoseWithCovariance
      Name: AMCL Pose
      Enabled: true
      Topic: /amcl_pose
      Covariance:
        Value: true
        Position:
          Value: true
          Alpha: 0.5
    - Class: rviz/Range
      Name: Sonar
      Enabled: true
      Topic: /sonar
      Alpha: 0.3
  Enabled: true
  Global Options:
    Background Color: 10; 20; 30
    Fixed Frame: odom
    Frame Rate: 20
    Default Light: false
  Name: root
  Tools:
    - Class: rviz/Interact
      Hide Inactive Objects: true
    - Class: rviz/MoveCamera
    - Class: rviz/SetGoal
      Topic: /move_base_simple/goal
  Value: true
  Views:
    Current:
      Class: rviz/TopDownOrtho
      Name: Current View
      Scale: 40
      Angle: -1.57
      X: 1.5
      Y: -2
      Target Frame: base_footprint
    Saved:
      - Class: rviz/Orbit
        Name: Behind
        Distance: 6
        Focal Point:
          X: 1
          Y: 2
          Z: 0.5
        Pitch: 0.4
        Yaw: 3.1
        Target Frame: base_link
      - Class: rviz/ThirdPersonFollower
        Name: Follow
        Distance: 3
        Target Frame: base_footprint
        Focal Shape Size: 0.1
      - Class: rviz/XYOrbit
        Name: Flat
        Distance: 8
      - Class: rviz/FPS
        Name: Eyes
        Position:
          X: -3
          Y: 0
          Z: 1.2
        Pitch: 0.2
        Yaw: 0.1
Window Geometry:
  Height: 700
  Width: 1000
  Hide Left Dock: false
"""


@pytest.fixture
def every_class(tmp_path: Path) -> RvizConfig:
    path = tmp_path / "every.rviz"
    path.write_text(EVERY_CLASS)
    return read_rviz(path)


def _by_name(config: RvizConfig) -> dict[str, RvizDisplay]:
    return {d.name: d for d in config.walk()}


def test_every_class_is_read_with_its_values(every_class: RvizConfig) -> None:
    config = every_class
    assert (config.fixed_frame, config.background, config.frame_rate) == ("odom", (10, 20, 30), 20)
    assert config.default_light is False
    d = _by_name(config)
    assert [(x.cls, x.name, x.enabled, x.line) for x in config.displays][:3] == [
        ("rviz/Grid", "Floor", True, 9),
        ("rviz/RobotModel", "Robot", True, 20),
        ("rviz/TF", "TF", True, 27),
    ]
    grid = d["Floor"]
    assert (grid.number("Cell Size"), grid.integer("Plane Cell Count")) == (0.5, 20)
    assert (grid.color(), grid.number("Alpha"), grid.text("Reference Frame")) == (
        (100, 100, 100),
        0.25,
        "odom",
    )
    assert (grid.text("Line Style"), grid.number("Line Style/Line Width")) == ("Billboards", 0.05)
    robot = d["Robot"]
    assert (robot.number("Alpha"), robot.flag("Visual Enabled")) == (0.5, False)
    assert (robot.flag("Collision Enabled"), robot.text("Robot Description")) == (
        True,
        "mbot_description",
    )
    tf = d["TF"]
    assert [tf.flag(k) for k in ("Show Names", "Show Axes", "Show Arrows")] == [False, True, False]
    assert (tf.number("Marker Scale"), tf.number("Frame Timeout")) == (0.5, 5.0)
    assert tf.flag("Frames/All Enabled") is False
    assert tf.properties["Frames"]["base_link"] == {"Value": True}
    scan = d["Scan"]
    assert (scan.kind, scan.topic, scan.number("Size (m)"), scan.number("Decay Time")) == (
        "LaserScan",
        "/scan",
        0.05,
        2.0,
    )
    assert (scan.text("Style"), scan.number("Alpha"), scan.integer("Queue Size")) == (
        "Points",
        0.8,
        5,
    )
    assert (scan.color(), scan.text("Color Transformer")) == ((255, 0, 0), "FlatColor")
    cloud = d["Cloud"]
    assert (cloud.kind, cloud.enabled, cloud.topic, cloud.text("Style")) == (
        "PointCloud2",
        False,
        "/camera/depth/points",
        "Spheres",
    )
    assert (d["Map"].kind, d["Map"].number("Alpha"), d["Map"].flag("Draw Behind")) == (
        "OccupancyGrid",
        0.6,
        True,
    )
    costmap = d["Local Costmap"]
    assert (costmap.kind, costmap.text("Color Scheme"), costmap.number("Alpha")) == (
        "Costmap",
        "costmap",
        0.4,
    )
    plan = d["Global Plan"]
    assert (plan.kind, plan.color(), plan.text("Line Style"), plan.integer("Buffer Length")) == (
        "Path",
        (0, 12, 255),
        "Billboards",
        3,
    )
    particles = d["ParticleCloud"]
    assert (particles.kind, particles.topic, particles.number("Arrow Length")) == (
        "PoseArray",
        "/particlecloud",
        0.5,
    )
    assert (particles.color(), particles.text("Shape")) == ((255, 0, 255), "Arrow (3D)")
    odom = d["Odometry"]
    assert (odom.integer("Keep"), odom.number("Position Tolerance")) == (20, 0.2)
    assert (odom.text("Shape"), odom.color("Shape/Color")) == ("Axes", (221, 200, 14))
    assert (odom.number("Shape/Axes Length"), odom.number("Shape/Shaft Length")) == (0.5, 1.0)
    image, camera = d["Image"], d["Camera"]
    assert (image.kind, image.topic, image.integer("Queue Size")) == (
        "Image",
        "/camera/rgb/image_raw",
        3,
    )
    assert (camera.kind, camera.topic, camera.number("Overlay Alpha")) == (
        "Camera",
        "/camera/rgb/image_raw",
        0.7,
    )
    marker, markers = d["Waypoints"], d["MarkerArray"]
    assert (marker.kind, marker.topic, marker.integer("Queue Size")) == (
        "Marker",
        "/waypoint_markers",
        50,
    )
    # rviz's default topic, a relative name, in the root namespace rviz runs in
    assert (markers.kind, markers.topic) == ("MarkerArray", "/visualization_marker_array")
    footprint = d["Footprint"]
    assert (footprint.kind, footprint.topic, footprint.color(), footprint.number("Alpha")) == (
        None,
        "/move_base/local_costmap/footprint",
        (0, 255, 0),
        0.5,
    )
    goal = d["Goal"]
    assert (goal.kind, goal.topic, goal.text("Shape"), goal.number("Axes Length")) == (
        "PoseStamped",
        "/move_base/current_goal",
        "Axes",
        0.7,
    )
    interact = d["Interact"]
    assert (interact.topic, interact.flag("Show Axes"), interact.flag("Show Descriptions")) == (
        "/basic_controls/update",
        True,
        False,
    )
    group = d["Sensors"]
    assert [(c.cls, c.name, c.enabled) for c in group.children] == [
        ("rviz/Axes", "Laser Axes", True),
        ("rviz/PointStamped", "Clicked", False),
    ]
    axes, clicked = group.children
    assert (axes.topic, axes.text("Reference Frame"), axes.number("Length")) == (
        None,
        "laser_link",
        0.3,
    )
    assert (clicked.topic, clicked.color(), clicked.integer("History Length")) == (
        "/clicked_point",
        (255, 255, 0),
        5,
    )
    assert d["Inflated Obstacles"].color() == (38, 190, 255)
    assert config.unknown == [
        "rviz/Polygon",
        "rviz/InteractiveMarkers",
        "rviz/Axes",
        "rviz/PointStamped",
        "rviz/GridCells",
        "rviz/PointCloud",
        "rviz/PoseWithCovariance",
        "rviz/Range",
    ]
    assert d["AMCL Pose"].number("Covariance/Position/Alpha") == 0.5
    assert (d["Sonar"].number("Alpha"), d["Old Cloud"].text("Style")) == (0.3, "Boxes")


def test_unset_properties_have_rvizs_defaults(every_class: RvizConfig) -> None:
    d = _by_name(every_class)
    scan, tf, robot = d["Scan"], d["TF"], d["Robot"]
    assert (d["Cloud"].number("Alpha"), d["Cloud"].integer("Queue Size")) == (1.0, 10)
    assert scan.flag("Use Fixed Frame") is True
    assert (tf.flag("Show Axes"), tf.number("Marker Alpha"), tf.number("Update Interval")) == (
        True,
        1.0,
        0.0,
    )
    assert (robot.flag("Visual Enabled"), robot.text("TF Prefix")) == (False, "")
    assert (d["Map"].text("Color Scheme"), d["Global Plan"].number("Alpha")) == ("map", 1.0)
    assert d["Global Plan"].text("Pose Style") == "None"
    assert d["ParticleCloud"].number("Head Length") == 0.07
    assert (d["Odometry"].number("Shape/Alpha"), d["Odometry"].flag("Covariance")) == (1.0, True)
    assert (d["Image"].text("Transport Hint"), d["Camera"].integer("Queue Size")) == ("raw", 2)
    assert d["MarkerArray"].integer("Queue Size") == 100
    assert d["Goal"].number("Shaft Length") == 1.0
    bare = RvizDisplay("rviz/LaserScan", "Scan")
    assert (bare.number("Size (m)"), bare.text("Style"), bare.integer("Queue Size")) == (
        0.01,
        "Flat Squares",
        10,
    )
    assert (bare.number("Decay Time"), bare.number("Alpha"), bare.topic) == (0.0, 1.0, None)
    fresh_map = RvizDisplay("rviz/Map", "Map")
    assert (fresh_map.number("Alpha"), fresh_map.text("Color Scheme")) == (0.7, "map")
    assert RvizDisplay("rviz/Path", "P").color() == (25, 255, 0)
    assert RvizDisplay("rviz/PoseArray", "P").number("Arrow Length") == 0.3


def test_views_are_read(every_class: RvizConfig) -> None:
    view = every_class.view
    assert (view.cls, view.name, view.number("Scale"), view.number("Angle")) == (
        "rviz/TopDownOrtho",
        "Current View",
        40.0,
        -1.57,
    )
    assert (view.number("X"), view.number("Y"), view.text("Target Frame")) == (
        1.5,
        -2.0,
        "base_footprint",
    )
    assert view.number("Near Clip Distance") == 0.01
    orbit, follow, flat, fps = every_class.saved_views
    assert (orbit.cls, orbit.name, orbit.number("Distance")) == ("rviz/Orbit", "Behind", 6.0)
    focal = [orbit.number(f"Focal Point/{a}") for a in "XYZ"]
    assert focal == [1.0, 2.0, 0.5]
    assert (orbit.number("Pitch"), orbit.number("Yaw"), orbit.text("Target Frame")) == (
        0.4,
        3.1,
        "base_link",
    )
    assert (follow.cls, follow.number("Distance"), follow.number("Focal Shape Size")) == (
        "rviz/ThirdPersonFollower",
        3.0,
        0.1,
    )
    assert (follow.number("Pitch"), follow.text("Target Frame")) == (0.785398, "base_footprint")
    assert (flat.cls, flat.number("Distance")) == ("rviz/XYOrbit", 8.0)
    assert (fps.cls, fps.number("Position/Z"), fps.number("Roll")) == ("rviz/FPS", 1.2, 0.0)


def test_a_config_without_views_or_options_has_rvizs(tmp_path: Path) -> None:
    path = tmp_path / "bare.rviz"
    path.write_text(
        "Visualization Manager:\n  Displays:\n    - {Class: rviz/Grid, Name: G}\n"
        "    - {Class: rviz/Axes, Value: true}\n"
    )
    config = read_rviz(path)
    assert (config.fixed_frame, config.background, config.frame_rate) == ("map", (48, 48, 48), 30)
    assert (config.view.cls, config.view.number("Distance"), config.view.number("Yaw")) == (
        "rviz/Orbit",
        10.0,
        0.785398,
    )
    # rviz leaves a display off unless the file says "Enabled: true"
    # (or its own checkbox, "Value"); a display without a name stays unnamed, as in rviz
    assert [(d.name, d.enabled) for d in config.displays] == [("G", False), ("", True)]
    (tmp_path / "empty.rviz").write_text("")
    assert read_rviz(tmp_path / "empty.rviz") == RvizConfig()


def test_a_hidden_left_dock_is_read(tmp_path: Path) -> None:
    """rviz opens a config with ``Hide Left Dock: true`` without its Displays panel; the
    viewer then opens with its side panel folded."""
    path = tmp_path / "bare.rviz"
    path.write_text(
        "Visualization Manager:\n  Displays: []\n"
        "Window Geometry: {Width: 1000, Height: 700, Hide Left Dock: true}\n"
    )
    assert read_rviz(path).hides_left_dock
    path.write_text("Window Geometry: {Hide Left Dock: false}\n")
    assert not read_rviz(path).hides_left_dock
    assert not RvizConfig.default().hides_left_dock


def test_the_course_configs_are_read() -> None:
    config = read_rviz(EXAMPLES / "mbot_description" / "config" / "mbot.rviz")
    assert config.fixed_frame == "base_footprint"
    assert [(d.kind, d.enabled) for d in config.displays] == [
        ("Grid", True),
        ("RobotModel", True),
        ("TF", True),
    ]
    arbotix = read_rviz(EXAMPLES / "mbot_description" / "config" / "mbot_arbotix.rviz")
    assert [(d.kind, d.topic, d.enabled) for d in arbotix.displays] == [
        ("Grid", None, True),
        ("RobotModel", None, True),
        ("Odometry", "/odom", True),
        ("TF", None, False),
    ]
    nav = read_rviz(EXAMPLES / "mbot_navigation" / "rviz" / "nav.rviz")
    assert [d.kind for d in nav.displays if d.cls == "rviz/Map"] == [
        "OccupancyGrid",
        "Costmap",
        "Costmap",
    ]
    assert (nav.view.cls, nav.view.number("Scale")) == ("rviz/TopDownOrtho", 40.0)
    assert nav.document["Visualization Manager"]["Tools"][3] == {
        "Class": "rviz/SetGoal",
        "Topic": "/move_base_simple/goal",
    }


def test_disabled_and_unsupported_displays_are_listed(tmp_path: Path) -> None:
    custom = tmp_path / "nav.rviz"
    custom.write_text(
        "Visualization Manager:\n  Global Options: {Fixed Frame: map}\n  Displays:\n"
        "    - {Class: rviz/LaserScan, Enabled: true, Name: Scan, Topic: /scan}\n"
        "    - {Class: rviz/Odometry, Enabled: false, Name: Odom, Topic: /odom}\n"
        "    - {Class: rviz_plugins/Fancy, Enabled: true, Name: X, Level: 3}\n"
    )
    config = read_rviz(custom)
    assert [(d.kind, d.topic, d.enabled) for d in config.displays] == [
        ("LaserScan", "/scan", True),
        ("Odometry", "/odom", False),
        (None, None, True),
    ]
    assert config.displays[2].properties == {"Level": 3}
    assert config.unknown == ["rviz_plugins/Fancy"]


ROS2 = """\
Visualization Manager:
  Class: ""
  Displays:
    - Class: rviz_default_plugins/LaserScan
      Enabled: true
      Name: LaserScan
      Size (m): 0.03
      Topic:
        Depth: 5
        Durability Policy: Volatile
        History Policy: Keep Last
        Reliability Policy: Best Effort
        Value: /scan
      Value: true
    - Class: rviz_default_plugins/Image
      Enabled: true
      Name: Image
      Topic:
        Value: /camera/image_raw
        Depth: 5
    - Class: rviz_common/Group
      Enabled: true
      Name: Nav
      Displays:
        - Class: rviz_default_plugins/Map
          Enabled: true
          Name: Map
          Topic: {Value: /map}
  Global Options:
    Background Color: 48; 48; 48
    Fixed Frame: map
    Frame Rate: 30
  Views:
    Current:
      Class: rviz_default_plugins/Orbit
      Distance: 5
      Name: Current View
"""


def test_ros2_configs_are_read_as_rviz1(tmp_path: Path) -> None:
    path = tmp_path / "ros2.rviz"
    path.write_text(ROS2)
    config = read_rviz(path)
    scan, image, group = config.displays
    assert (scan.cls, scan.kind, scan.topic, scan.number("Size (m)")) == (
        "rviz/LaserScan",
        "LaserScan",
        "/scan",
        0.03,
    )
    assert scan.properties["Topic"]["Reliability Policy"] == "Best Effort"
    assert (image.cls, image.topic, image.topic_key) == (
        "rviz/Image",
        "/camera/image_raw",
        "Image Topic",
    )
    assert (group.cls, [(c.cls, c.topic) for c in group.children]) == (
        "rviz/Group",
        [("rviz/Map", "/map")],
    )
    assert (config.view.cls, config.view.number("Distance")) == ("rviz/Orbit", 5.0)


@pytest.mark.parametrize(
    ("text", "where", "what"),
    [
        ("- just\n- a list\n", r"bad\.rviz:1:1:", "an rviz config must be a mapping"),
        ("Visualization Manager: 3\n", r"bad\.rviz:1:24:", "Visualization Manager must be"),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/Grid\n    - 7\n",
            r"bad\.rviz:4:7:",
            "a display must be a mapping, got 7",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Name: Scan\n      Topic: /scan\n",
            r"bad\.rviz:3:7:",
            "a display without 'Class'",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/Path\n      Color: 255; 0\n",
            r"bad\.rviz:4:14:",
            r"'Color': expected a colour 'R; G; B'",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/LaserScan\n"
            "      Topic: /scan\n      Size (m): big\n",
            r"bad\.rviz:5:17:",
            "'Size \\(m\\)' must be a number, got 'big'",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/Grid\n"
            "      Line Style:\n        Value: Lines\n        Line Width: thin\n",
            r"bad\.rviz:6:21:",
            "'Line Style/Line Width' must be a number",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/Group\n      Displays:\n"
            "        - Class: rviz/TF\n          Show Names: 2\n",
            r"bad\.rviz:6:23:",
            "'Show Names' must be true or false, got 2",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/TF\n      Enabled: yes?\n",
            r"bad\.rviz:4:16:",
            "'Enabled' must be true or false",
        ),
        (
            "Visualization Manager:\n  Global Options:\n    Background Color: black\n",
            r"bad\.rviz:3:23:",
            "'Background Color': expected a colour",
        ),
        (
            "Visualization Manager:\n  Global Options:\n    Frame Rate: " + "9" * 400 + "\n",
            r"bad\.rviz:3:17:",
            "'Frame Rate' is out of range, got 99999999999999999999…",
        ),
        (
            "Visualization Manager:\n  Displays:\n    - Class: rviz/LaserScan\n"
            "      Decay Time: .inf\n",
            r"bad\.rviz:4:19:",
            "'Decay Time' is out of range, got inf",
        ),
        (
            "Visualization Manager:\n  Global Options:\n    Frame Rate: fast\n",
            r"bad\.rviz:3:17:",
            "'Frame Rate' must be a number",
        ),
        (
            "Visualization Manager:\n  Views:\n    Current:\n      Class: rviz/Orbit\n"
            "      Focal Point: {X: 1, Y: a, Z: 0}\n",
            r"bad\.rviz:5:30:",
            "'Focal Point/Y' must be a number",
        ),
        (
            "Visualization Manager:\n  Displays: {Class: rviz/Grid}\n",
            r"bad\.rviz:2:13:",
            "Displays must be a list, got a mapping",
        ),
        ("Visualization Manager:\n  Displays: [\n", r"bad\.rviz:3:1:", "invalid YAML"),
    ],
)
def test_bad_configs_are_one_located_error(
    tmp_path: Path, text: str, where: str, what: str
) -> None:
    path = tmp_path / "bad.rviz"
    path.write_text(text)
    with pytest.raises(ParseError, match=f"/{where} error: {what}"):
        read_rviz(path)


def test_a_missing_file_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(BelvedereError, match=r"cannot read rviz config .*none\.rviz"):
        read_rviz(tmp_path / "none.rviz")


def test_colors() -> None:
    assert parse_color("255; 0; 0") == (255, 0, 0)
    assert parse_color(" 1;2 ; 3 ") == (1, 2, 3)
    assert format_color((25, 255, 0)) == "25; 255; 0"
    for bad in ("255; 0", "red", "256; 0; 0", "1; 2; 3; 4", "-1; 0; 0"):
        with pytest.raises(ValueError, match="expected a colour"):
            parse_color(bad)


def test_read_write_read_is_equal_and_keeps_what_is_not_modelled(
    tmp_path: Path, every_class: RvizConfig
) -> None:
    out = tmp_path / "out.rviz"
    write_rviz(every_class, out)
    again = read_rviz(out)
    assert again == every_class
    assert again.displays == every_class.displays
    assert again.saved_views == every_class.saved_views
    for section in ("Panels", "Window Geometry"):
        assert again.document[section] == every_class.document[section]
    manager = again.document["Visualization Manager"]
    assert manager["Tools"] == every_class.document["Visualization Manager"]["Tools"]
    assert (manager["Name"], manager["Value"]) == ("root", True)
    assert _by_name(again)["TF"].properties["Frames"]["base_link"] == {"Value": True}
    assert out.read_text() == (tmp_path / "out.rviz").read_text()
    write_rviz(again, tmp_path / "twice.rviz")
    assert (tmp_path / "twice.rviz").read_text() == out.read_text()


def test_edits_are_written(tmp_path: Path, every_class: RvizConfig) -> None:
    config = every_class
    d = _by_name(config)
    d["Scan"].set("Topic", "/base_scan")
    d["Floor"].set("Line Style", "Lines")
    d["Odometry"].set("Shape/Color", "1; 2; 3")
    d["Cloud"].enabled = True
    config.displays.append(RvizDisplay("rviz/Pose", "New", True, {"Topic": "/goal"}))
    config.fixed_frame, config.background = "map", (1, 2, 3)
    config.view = RvizView("rviz/Orbit", "Current View", {"Distance": 4.5})
    write_rviz(config, tmp_path / "edited.rviz")
    again = read_rviz(tmp_path / "edited.rviz")
    e = _by_name(again)
    assert (e["Scan"].topic, e["Floor"].text("Line Style")) == ("/base_scan", "Lines")
    assert e["Floor"].number("Line Style/Line Width") == 0.05
    assert (e["Odometry"].color("Shape/Color"), e["Cloud"].enabled) == ((1, 2, 3), True)
    assert (e["New"].cls, e["New"].topic, e["New"].enabled) == ("rviz/Pose", "/goal", True)
    assert (again.fixed_frame, again.background) == ("map", (1, 2, 3))
    assert (again.view.cls, again.view.number("Distance")) == ("rviz/Orbit", 4.5)


def test_the_default_config_is_rvizs() -> None:
    config = RvizConfig.default()
    assert (config.fixed_frame, config.background, config.frame_rate) == ("map", (48, 48, 48), 30)
    assert [(d.cls, d.name, d.enabled) for d in config.displays] == [("rviz/Grid", "Grid", True)]
    assert (config.view.cls, config.view.number("Distance")) == ("rviz/Orbit", 10.0)
    tools = [t["Class"] for t in config.document["Visualization Manager"]["Tools"]]
    assert "rviz/SetGoal" in tools
    assert config.document["Panels"][0]["Class"] == "rviz/Displays"


def test_an_unwritable_place_is_one_error_and_loses_nothing(
    tmp_path: Path, every_class: RvizConfig
) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(FileWriteError, match=r"cannot write .*file/out\.rviz: Not a directory"):
        write_rviz(every_class, blocker / "out.rviz")
    with pytest.raises(FileWriteError, match=r"Is a directory"):
        write_rviz(every_class, tmp_path)
    kept = tmp_path / "kept.rviz"
    kept.write_text(EVERY_CLASS)
    every_class.displays[0].set("Alpha", object())  # cannot be written as YAML
    with pytest.raises(BelvedereError, match=r"cannot write .*kept\.rviz: .*'Floor'.*'Alpha'"):
        write_rviz(every_class, kept)
    assert kept.read_text() == EVERY_CLASS
    assert sorted(os.listdir(tmp_path)) == ["every.rviz", "file", "kept.rviz"]


# --- Debian's rviz 1.14 as the oracle -------------------------------------------------------

needs_rviz = pytest.mark.skipif(missing_rviz() is not None, reason=str(missing_rviz()))


@pytest.fixture(scope="module")
def roscore(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Roscore]:
    yield from start_roscore(tmp_path_factory.mktemp("rviz_ros_home"))


def _same(ours: Any, theirs: Any) -> bool:
    """rviz keeps numbers as float32 and writes them back as doubles."""
    if isinstance(ours, bool) or isinstance(theirs, bool):
        return type(ours) is type(theirs) and bool(ours) == bool(theirs)
    if isinstance(ours, int | float) and isinstance(theirs, int | float):
        return math.isclose(ours, theirs, rel_tol=1e-6, abs_tol=1e-7)
    if isinstance(ours, dict) and isinstance(theirs, dict):
        return all(k in theirs and _same(v, theirs[k]) for k, v in ours.items())
    same: bool = ours == theirs
    return same


def _differences(
    ours: Mapping[str, Any], theirs: RvizDisplay | RvizView, defaults: Mapping[str, Any]
) -> list[str]:
    """What rviz did not keep of ours, and where its defaults differ from our table."""
    wrong = [
        f"{theirs.name}: {key}: ours {value!r}, rviz {theirs.properties.get(key)!r}"
        for key, value in ours.items()
        if not _same(value, theirs.properties.get(key))
    ]
    for path, default in defaults.items():
        if path.split("/")[0] in ours:
            continue
        found, value = theirs._lookup(path)
        if not found or not _same(default, value):
            wrong.append(f"{theirs.name}: default {path}: ours {default!r}, rviz {value!r}")
    return wrong


@needs_rviz
def test_rviz_opens_what_we_write_and_keeps_our_values(
    tmp_path: Path, roscore: Roscore, every_class: RvizConfig
) -> None:
    written = tmp_path / "ours.rviz"
    write_rviz(every_class, written)
    saved = tmp_path / "saved_by_rviz.rviz"
    run = open_in_rviz(written, roscore, tmp_path, save_to=saved)
    assert run.came_up, run.output
    assert run.complaints() == [], run.output
    theirs = read_rviz(saved)
    assert (theirs.fixed_frame, theirs.background, theirs.frame_rate) == ("odom", (10, 20, 30), 20)
    assert theirs.default_light is False
    ours_all, theirs_all = list(every_class.walk()), list(theirs.walk())
    assert [(d.cls, d.name, d.enabled) for d in theirs_all] == [
        (d.cls, d.name, d.enabled) for d in ours_all
    ]
    wrong: list[str] = []
    for ours, rviz in zip(ours_all, theirs_all, strict=True):
        ours_props = dict(ours.properties)
        if ours.cls == "rviz/TF":  # rviz lists only the frames it has seen on /tf
            ours_props["Frames"] = {"All Enabled": ours.properties["Frames"]["All Enabled"]}
        wrong += _differences(ours_props, rviz, DEFAULTS[ours.cls])
    for ours_view, rviz_view in zip(
        [every_class.view, *every_class.saved_views],
        [theirs.view, *theirs.saved_views],
        strict=True,
    ):
        assert (rviz_view.cls, rviz_view.name) == (ours_view.cls, ours_view.name)
        wrong += _differences(ours_view.properties, rviz_view, VIEW_DEFAULTS[ours_view.cls])
    assert wrong == [], "\n".join(wrong)
    assert theirs.document["Visualization Manager"]["Tools"][2]["Topic"] == "/move_base_simple/goal"


@needs_rviz
def test_rviz_opens_the_default_and_a_ros2_config_as_we_write_them(
    tmp_path: Path, roscore: Roscore
) -> None:
    source = tmp_path / "ros2.rviz"
    source.write_text(ROS2)
    config = read_rviz(source)
    config.displays.append(RvizConfig.default().displays[0])
    config.document["Panels"] = RvizConfig.default().document["Panels"]
    written = tmp_path / "ours.rviz"
    write_rviz(config, written)
    saved = tmp_path / "saved_by_rviz.rviz"
    run = open_in_rviz(written, roscore, tmp_path, save_to=saved)
    assert run.came_up, run.output
    assert run.complaints() == [], run.output
    theirs = read_rviz(saved)
    assert [(d.cls, d.topic, d.enabled) for d in theirs.walk()] == [
        ("rviz/LaserScan", "/scan", True),
        ("rviz/Image", "/camera/image_raw", True),
        ("rviz/Group", None, True),
        ("rviz/Map", "/map", True),
        ("rviz/Grid", None, True),
    ]
    assert theirs.displays[0].number("Size (m)") == pytest.approx(0.03)
    assert [p["Class"] for p in theirs.document["Panels"]] == [
        "rviz/Displays",
        "rviz/Selection",
        "rviz/Tool Properties",
        "rviz/Views",
        "rviz/Time",
    ]


@needs_rviz
def test_the_oracle_is_not_blind_to_a_class_rviz_lacks(tmp_path: Path, roscore: Roscore) -> None:
    config = RvizConfig.default()
    config.displays.append(RvizDisplay("rviz_plugins/Fancy", "Fancy", True, {"Level": 3}))
    written = tmp_path / "unknown.rviz"
    write_rviz(config, written)
    run = open_in_rviz(written, roscore, tmp_path, save_to=None)
    assert run.came_up, run.output
    assert any(
        "[ERROR]" in line and "'rviz_plugins/Fancy' failed to load" in line
        for line in run.complaints()
    ), run.output
