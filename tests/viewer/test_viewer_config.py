"""The viewer and ``.rviz`` configs: every entry becomes a display with its Enabled flag and
values (groups, nested values, classes we do not draw), and File > Save Config writes back a
config that reads the same and that Debian's rviz opens."""

from __future__ import annotations

import socket
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.description.urdf import RobotModel
from belvedere.graph import Graph
from belvedere.viewer import Viewer, read_rviz
from belvedere.viewer._status import Level
from tests.conftest import EXAMPLES
from tests.tf.ros1 import Roscore, start_roscore
from tests.viewer.rviz_oracle import missing_rviz, open_in_rviz

MBOT = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
CONFIG = """\
Panels:
  - Class: rviz/Displays
    Name: Displays
Visualization Manager:
  Class: ""
  Displays:
    - Class: rviz/Grid
      Enabled: true
      Name: Grid
      Cell Size: 0.5
      Color: 100; 100; 100
    - Class: rviz/Group
      Enabled: true
      Name: Navigation
      Displays:
        - Class: rviz/Map
          Enabled: true
          Name: Costmap
          Topic: /move_base/local_costmap/costmap
          Color Scheme: costmap
          Alpha: 0.4
        - Class: rviz/Path
          Enabled: false
          Name: Plan
          Topic: /plan
          Color: 0; 0; 255
          Line Style:
            Line Width: 0.05
            Value: Billboards
    - Class: rviz/LaserScan
      Enabled: true
      Name: Scan
      Topic: /scan
      Decay Time: 2
      Size (m): 0.05
    - Class: rviz/Image
      Enabled: true
      Name: Camera view
      Image Topic: /camera/image_raw
    - Class: rviz_plugins/Fancy
      Enabled: true
      Name: Fancy
      Whatever: 3
  Global Options:
    Background Color: 10; 20; 30
    Fixed Frame: odom
    Frame Rate: 20
  Views:
    Current:
      Class: rviz/TopDownOrtho
      Name: Current View
      Scale: 40
      Target Frame: <Fixed Frame>
      X: 1
      Y: 2
"""


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@pytest.fixture
def viewer(tmp_path: Path) -> Iterator[Viewer]:
    path = tmp_path / "nav.rviz"
    path.write_text(CONFIG)
    graph = Graph(sim_time=False)
    v = Viewer(graph, port=_port(), rviz=read_rviz(path), rviz_path=path)
    yield v
    v.close()
    graph.shutdown()


def test_the_course_config_shows_what_it_enables() -> None:
    """mbot.rviz enables Grid, RobotModel and TF (TF was ignored before)."""
    graph = Graph(sim_time=False)
    config = read_rviz(EXAMPLES / "mbot_description/config/mbot.rviz")
    v = Viewer(graph, model=RobotModel.from_path(MBOT), port=_port(), rviz=config)
    try:
        assert [(d.type_name, d.enabled) for d in v.displays] == [
            ("Grid", True),
            ("RobotModel", True),
            ("TF", True),
        ]
        assert v.fixed_frame == "base_footprint"
    finally:
        v.close()
        graph.shutdown()


def test_every_entry_becomes_a_display_with_its_values(viewer: Viewer) -> None:
    by_name = {d.name: d for d in viewer.displays}
    assert list(by_name) == ["Grid", "Costmap", "Plan", "Scan", "Camera view", "Fancy"]
    assert by_name["Grid"].values["Color"] == (100, 100, 100)
    assert by_name["Costmap"].values["Color Scheme"] == "costmap"
    assert by_name["Costmap"].values["Alpha"] == pytest.approx(0.4)
    assert by_name["Costmap"].topic == "/move_base/local_costmap/costmap"
    plan = by_name["Plan"]
    assert not plan.enabled
    assert (plan.values["Line Style"], plan.values["Line Width"]) == ("Billboards", 0.05)
    assert plan.values["Color"] == (0, 0, 255)
    assert by_name["Scan"].values["Decay Time"] == 2.0
    assert by_name["Camera view"].topic == "/camera/image_raw"
    fancy = by_name["Fancy"]
    assert fancy.level is Level.ERROR
    assert "'rviz_plugins/Fancy', could not be loaded" in fancy.status.markdown()
    assert (viewer.fixed_frame, viewer.rate_hz) == ("odom", 20.0)
    assert tuple(viewer.background.value) == (10, 20, 30)


def test_saved_config_reads_back_the_same(viewer: Viewer, tmp_path: Path) -> None:
    by_name = {d.name: d for d in viewer.displays}
    by_name["Scan"].set_value("Decay Time", 5.0)
    by_name["Scan"].name = "Front laser"
    by_name["Plan"].set_enabled(True)
    by_name["Plan"].set_value("Line Width", 0.1)
    viewer.set_fixed_frame("map")
    saved = viewer.save_config(tmp_path / "saved.rviz")
    config = read_rviz(saved)
    entries = list(config.walk())
    assert [(d.cls, d.name, d.enabled) for d in entries] == [
        ("rviz/Grid", "Grid", True),
        ("rviz/Group", "Navigation", True),
        ("rviz/Map", "Costmap", True),
        ("rviz/Path", "Plan", True),
        ("rviz/LaserScan", "Front laser", True),
        ("rviz/Image", "Camera view", True),
        ("rviz_plugins/Fancy", "Fancy", True),
    ]
    laser = entries[4]
    assert (laser.topic, laser.number("Decay Time"), laser.number("Size (m)")) == (
        "/scan",
        5.0,
        0.05,
    )
    plan = entries[3]
    assert plan.get("Line Style/Line Width") == pytest.approx(0.1)
    assert plan.get("Line Style") == "Billboards"
    assert plan.color() == (0, 0, 255)
    assert entries[5].topic == "/camera/image_raw"
    assert entries[6].properties["Whatever"] == 3
    assert (config.fixed_frame, config.background, config.frame_rate) == ("map", (10, 20, 30), 20)
    assert config.view.cls == "rviz/TopDownOrtho"
    assert config.document["Panels"][0]["Class"] == "rviz/Displays"  # kept as it was
    # the group is written again, around the displays it had
    group = config.displays[1]
    assert (group.cls, group.name, group.enabled) == ("rviz/Group", "Navigation", True)
    assert [d.name for d in group.children] == ["Costmap", "Plan"]
    assert [d.name for d in config.displays] == [
        "Grid",
        "Navigation",
        "Front laser",
        "Camera view",
        "Fancy",
    ]


def test_a_disabled_group_keeps_its_displays_own_flags(tmp_path: Path) -> None:
    """Displays inside a disabled group are off, and saved with their own Enabled flags."""
    path = tmp_path / "group.rviz"
    on, off = (f"      Enabled: {flag}\n      Name: Navigation" for flag in ("true", "false"))
    path.write_text(CONFIG.replace(on, off))
    graph = Graph(sim_time=False)
    v = Viewer(graph, port=_port(), rviz=read_rviz(path), rviz_path=path)
    try:
        assert [d.enabled for d in v.displays if d.name in ("Costmap", "Plan")] == [False, False]
        group = read_rviz(v.save_config(tmp_path / "saved.rviz")).displays[1]
        assert (group.name, group.enabled) == ("Navigation", False)
        assert [(d.name, d.enabled) for d in group.children] == [
            ("Costmap", True),
            ("Plan", False),
        ]
    finally:
        v.close()
        graph.shutdown()


@pytest.fixture(scope="module")
def roscore(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Roscore]:
    reason = missing_rviz()
    if reason is not None:
        pytest.skip(reason)
    yield from start_roscore(tmp_path_factory.mktemp("viewer_rviz_home"))


def test_debian_rviz_opens_the_saved_config(
    viewer: Viewer, tmp_path: Path, roscore: Roscore
) -> None:
    # rviz reports the class it cannot load: save without our unsupported one
    fancy = next(d for d in viewer.displays if d.name == "Fancy")
    viewer.remove_display(fancy)
    saved = viewer.save_config(tmp_path / "ours.rviz")
    again = tmp_path / "saved_by_rviz.rviz"
    run = open_in_rviz(saved, roscore, tmp_path, save_to=again)
    assert run.came_up, run.output
    assert run.complaints() == [], run.output
    theirs = [(d.cls, d.name, d.enabled) for d in read_rviz(again).walk()]
    assert theirs == [(d.cls, d.name, d.enabled) for d in read_rviz(saved).walk()]
