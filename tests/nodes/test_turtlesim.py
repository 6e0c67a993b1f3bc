"""turtlesim's executables on one graph in simulated time: turtlesim_node's names, parameters
and services, mimic and draw_square, as a launch file starts them."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph, ServiceFailedError
from belvedere.launch import load_launch
from belvedere.launch._runtime import LaunchRuntime
from belvedere.packages import PackageIndex
from belvedere.sim.turtlesim import SIZE
from belvedere.teleop import TurtleKeys


def _launch(tmp_path: Path, body: str) -> tuple[Graph, LaunchRuntime]:
    path = tmp_path / "t.launch"
    path.write_text(f"<launch>{body}</launch>")
    packages = PackageIndex([tmp_path])
    graph = Graph()
    runtime = LaunchRuntime(load_launch(path, packages=packages), graph, packages, headless=True)
    runtime.start()
    assert not runtime.missing
    return graph, runtime


SIM = '<node pkg="turtlesim" type="turtlesim_node" name="sim"/>'


def test_names_parameters_and_services(tmp_path: Path) -> None:
    graph, runtime = _launch(
        tmp_path, SIM.replace("/>", '><param name="background_r" value="5"/></node>')
    )
    assert graph.params.get("/sim/background_r") == 5
    assert graph.params.get("/sim/background_g") == 86
    assert graph.params.get("/sim/background_b") == 255
    probe = graph.create_node("probe")
    poses: list[Any] = []
    colors: list[Any] = []
    probe.subscribe("/turtle1/pose", "turtlesim/Pose", poses.append, queue_size=0)
    probe.subscribe("/turtle1/color_sensor", "turtlesim/Color", colors.append, queue_size=0)
    graph.run(duration=1.0)
    assert len(poses) == pytest.approx(62, abs=1)  # 62.5 Hz
    assert (poses[-1].x, poses[-1].y) == pytest.approx((SIZE / 2, SIZE / 2))
    assert (colors[-1].r, colors[-1].g, colors[-1].b) == (5, 86, 255)

    answer = probe.call_service("/spawn", "turtlesim/Spawn", {"x": 2.0, "y": 3.0, "name": ""})
    assert answer.name == "turtle2"
    with pytest.raises(ServiceFailedError, match="already exists"):
        probe.call_service("/spawn", "turtlesim/Spawn", {"name": "turtle2"})
    assert "/turtle2/teleport_absolute" in graph.services
    probe.call_service("/turtle2/set_pen", "turtlesim/SetPen", {"r": 255, "width": 4})
    cmd = probe.publisher("/turtle2/cmd_vel", "geometry_msgs/Twist")
    cmd.publish_data({"linear": {"x": 1.0}})
    seen: list[Any] = []
    probe.subscribe("/turtle2/pose", "turtlesim/Pose", seen.append, queue_size=0)
    graph.run(duration=1.5)
    assert seen[-1].x == pytest.approx(3.0, abs=0.02)  # 1 m/s for 1 s, then stopped
    assert seen[-1].linear_velocity == 0.0

    graph.params.set("/sim/background_b", 0.4)  # roscpp rounds a double
    probe.call_service("/clear", "std_srvs/Empty")
    graph.run(duration=0.1)
    assert (colors[-1].r, colors[-1].g, colors[-1].b) == (5, 86, 0)

    teleport = ("/turtle2/teleport_absolute", "turtlesim/TeleportAbsolute")
    with pytest.raises(ServiceFailedError, match=r"cannot teleport turtle2 to x=nan"):
        probe.call_service(*teleport, {"x": math.nan})
    with pytest.raises(ServiceFailedError, match=r"cannot spawn a turtle at x=inf"):
        probe.call_service("/spawn", "turtlesim/Spawn", {"x": math.inf})
    probe.call_service("/kill", "turtlesim/Kill", {"name": "turtle2"})
    assert "/turtle2/set_pen" not in graph.services
    assert "/turtle2/pose" not in {t for t, topic in graph.topics.items() if topic.publishers}
    with pytest.raises(ServiceFailedError, match="does not exist"):
        probe.call_service("/kill", "turtlesim/Kill", {"name": "turtle2"})
    probe.call_service("/spawn", "turtlesim/Spawn", {"x": 1.0, "y": 1.0, "name": "leo"})
    probe.call_service("/reset", "std_srvs/Empty")
    assert "/leo/set_pen" not in graph.services
    assert "/turtle1/set_pen" in graph.services
    runtime.close()
    graph.shutdown()


def test_a_bad_background_is_named_and_the_default_used(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    graph, runtime = _launch(
        tmp_path, SIM.replace("/>", '><param name="background_g" value="green"/></node>')
    )
    colors: list[Any] = []
    graph.create_node("probe").subscribe("/turtle1/color_sensor", "turtlesim/Color", colors.append)
    graph.run(duration=0.1)
    assert (colors[-1].r, colors[-1].g, colors[-1].b) == (69, 86, 255)
    assert "/sim/background_g is 'green', not an integer 0-255: using 86" in caplog.text
    runtime.close()
    graph.shutdown()


def test_mimic_follows_turtle1_with_turtle2(tmp_path: Path) -> None:
    graph, runtime = _launch(
        tmp_path,
        SIM
        + """<node pkg="turtlesim" type="mimic" name="mimic">
               <remap from="input" to="turtle1"/><remap from="output" to="turtle2"/>
             </node>""",
    )
    probe = graph.create_node("probe")
    probe.call_service("/spawn", "turtlesim/Spawn", {"x": 2.0, "y": 2.0, "name": "turtle2"})
    poses: dict[str, Any] = {}
    probe.subscribe("/turtle1/pose", "turtlesim/Pose", lambda m: poses.update(turtle1=m))
    probe.subscribe("/turtle2/pose", "turtlesim/Pose", lambda m: poses.update(turtle2=m))
    probe.publisher("/turtle1/cmd_vel", "geometry_msgs/Twist").publish_data(
        {"linear": {"x": 1.0}, "angular": {"z": 0.5}}
    )
    graph.run(duration=2.0)
    one, two = poses["turtle1"], poses["turtle2"]
    assert one.theta == pytest.approx(0.5, abs=0.02)  # 1 s of turning
    # turtle2 does what turtle1 did, a pose (one update) behind
    assert two.theta == pytest.approx(one.theta, abs=0.02)
    assert two.x - 2.0 == pytest.approx(one.x - SIZE / 2, abs=0.03)
    runtime.close()
    graph.shutdown()


def test_draw_square_draws_a_2_m_square(tmp_path: Path) -> None:
    graph, runtime = _launch(tmp_path, SIM + '<node pkg="turtlesim" type="draw_square" name="sq"/>')
    corners: list[tuple[float, float]] = []
    last: list[Any] = []

    def on_pose(msg: Any) -> None:
        if last and last[0].linear_velocity > 0 and msg.linear_velocity == 0:
            corners.append((msg.x, msg.y))
        last[:] = [msg]

    graph.create_node("probe").subscribe("/turtle1/pose", "turtlesim/Pose", on_pose, queue_size=0)
    graph.run(duration=22.0)  # four sides (2 s each) and four quarter turns (~4 s each)
    assert len(corners) >= 4
    c = SIZE / 2
    want = [(c + 2, c), (c + 2, c + 2), (c, c + 2), (c, c)]
    for (x, y), (wx, wy) in zip(corners[:4], want, strict=True):
        assert math.hypot(x - wx, y - wy) < 0.15
    runtime.close()
    graph.shutdown()


def test_turtle_teleop_keys() -> None:
    keys = TurtleKeys()
    assert keys.key("\x1b").twist is None  # an arrow's ESC and [ send nothing
    assert keys.key("[").twist is None
    assert keys.key("A").twist == (2.0, 0.0, 0.0, 0.0)
    assert keys.key("B").twist == (-2.0, 0.0, 0.0, 0.0)
    assert keys.key("D").twist == (0.0, 0.0, 0.0, 2.0)
    assert keys.key("C").twist == (0.0, 0.0, 0.0, -2.0)
    assert keys.key("x").twist is None
    assert keys.key("q").quit
