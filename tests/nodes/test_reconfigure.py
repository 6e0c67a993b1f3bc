"""move_base and its local planner reconfigured as rqt_reconfigure and dynparam do it: through
``set_parameters``, with ROS's names, ranges and topics, and the robot's motion changing."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from belvedere.graph import ActionClient, Graph, ServiceFailedError
from belvedere.msgs import message_to_data
from belvedere.ros1.dynamic_reconfigure._description import config_data, config_values
from tests.nodes.test_amcl import (
    AMCL,
    SIM,
    pkg,  # noqa: F401 (the map package fixture)
)
from tests.nodes.test_amcl import _start as start_amcl
from tests.nodes.test_move_base import _goal, _launch, _start


def _set(probe: Any, service: str, values: dict[str, Any]) -> dict[str, Any]:
    reply = probe.call_service(
        service, "dynamic_reconfigure/Reconfigure", {"config": config_data(values, [])}
    )
    return config_values(message_to_data(reply.config))


@pytest.fixture
def nav(tmp_path: Path) -> Any:
    graph = _start(_launch(tmp_path))
    probe = graph.create_node("probe")
    yield graph, probe
    graph.shutdown()


def test_move_base_describes_and_takes_its_parameters(nav: tuple[Graph, Any]) -> None:
    graph, probe = nav
    descriptions: list[Any] = []
    updates: list[Any] = []
    probe.subscribe(
        "/move_base/parameter_descriptions",
        "dynamic_reconfigure/ConfigDescription",
        descriptions.append,
    )
    probe.subscribe("/move_base/parameter_updates", "dynamic_reconfigure/Config", updates.append)
    graph.run(duration=0.5)
    (described,) = descriptions
    names = [p.name for p in described.groups[0].parameters]
    assert "controller_frequency" in names
    assert "oscillation_distance" in names
    maxima = config_values(message_to_data(described.max))
    assert maxima["controller_frequency"] == 100.0
    # clamped to MoveBase.cfg's range, as ROS's server clamps
    after = _set(probe, "/move_base/set_parameters", {"oscillation_timeout": 500.0})
    assert after["oscillation_timeout"] == 60.0
    assert graph.params.get("/move_base/oscillation_timeout") == 60.0
    graph.run(duration=0.2)
    assert config_values(message_to_data(updates[-1]))["oscillation_timeout"] == 60.0
    with pytest.raises(ServiceFailedError, match="cannot change while move_base runs"):
        _set(probe, "/move_base/set_parameters", {"base_local_planner": "other/Planner"})
    with pytest.raises(ServiceFailedError, match="no parameter 'speed'"):
        _set(probe, "/move_base/set_parameters", {"speed": 1.0})


def test_a_slower_local_planner_drives_slower(nav: tuple[Graph, Any]) -> None:
    graph, probe = nav
    speeds: list[float] = []
    probe.subscribe("/cmd_vel", "geometry_msgs/Twist", lambda m: speeds.append(m.linear.x))
    graph.run(duration=0.5)
    planner = "/move_base/TrajectoryPlannerROS/set_parameters"
    after = _set(probe, planner, {"max_vel_x": 0.12, "min_vel_x": 0.05})
    assert after["max_vel_x"] == pytest.approx(0.12)
    assert graph.params.get("/move_base/TrajectoryPlannerROS/max_vel_x") == pytest.approx(0.12)
    client = ActionClient(probe, "/move_base", "move_base_msgs/MoveBase")
    client.send_goal(_goal(3.0, 0.0, 0.0))
    graph.run(duration=8.0)
    assert speeds
    assert max(speeds) <= 0.12 + 1e-9
    assert max(speeds) > 0.05
    # and a maximum below the minimum is refused, leaving the planner as it was
    with pytest.raises(ServiceFailedError, match="maximum is below the minimum"):
        _set(probe, planner, {"max_vel_x": 0.01})
    assert math.isclose(graph.params.get("/move_base/TrajectoryPlannerROS/max_vel_x"), 0.12)


def test_amcl_takes_a_new_configuration_and_keeps_localizing(pkg: Path) -> None:  # noqa: F811
    graph = start_amcl(pkg, SIM + AMCL.format(extra=""), "reconfigure.launch")
    probe = graph.create_node("probe")
    poses: list[Any] = []
    probe.subscribe("/amcl_pose", "geometry_msgs/PoseWithCovarianceStamped", poses.append)
    probe.publisher("/cmd_vel", "geometry_msgs/Twist", latch=True).publish_data(
        {"linear": {"x": 0.3}}
    )
    try:
        graph.run(duration=2.0)
        assert poses
        after = _set(
            probe, "/amcl/set_parameters", {"laser_max_beams": 900, "odom_model_type": "diff"}
        )
        assert after["laser_max_beams"] == 250  # AMCL.cfg's maximum
        assert graph.params.get("/amcl/laser_max_beams") == 250
        with pytest.raises(ServiceFailedError, match="none of its enum's values"):
            _set(probe, "/amcl/set_parameters", {"odom_model_type": "tracks"})
        count = len(poses)
        graph.run(duration=3.0)
        assert len(poses) > count  # the filter, made anew, goes on from its estimate
        last = poses[-1].pose.pose.position
        assert last.y == pytest.approx(-4.5, abs=0.3)
        assert last.x > 0.5
    finally:
        graph.shutdown()


def test_a_wider_inflation_radius_inflates_the_global_costmap_further(
    nav: tuple[Graph, Any],
) -> None:
    graph, probe = nav
    costmap: dict[str, Any] = {}

    def on_full(msg: Any) -> None:
        costmap["grid"] = np.asarray(msg.data).reshape(msg.info.height, msg.info.width)

    def on_update(msg: Any) -> None:  # costmap_2d's updates: a box of changed cells
        box = np.asarray(msg.data).reshape(msg.height, msg.width)
        costmap["grid"][msg.y : msg.y + msg.height, msg.x : msg.x + msg.width] = box

    topic = "/move_base/global_costmap/costmap"
    probe.subscribe(topic, "nav_msgs/OccupancyGrid", on_full)
    probe.subscribe(topic + "_updates", "map_msgs/OccupancyGridUpdate", on_update)
    # rbx1's blank map is walled all round: inflated cells line its border
    graph.run(duration=2.5)

    def inflated() -> int:
        data = costmap["grid"]
        return int(np.count_nonzero((data > 0) & (data < 100)))

    before = inflated()
    assert before > 0
    layer = "/move_base/global_costmap/inflation_layer/set_parameters"
    after = _set(probe, layer, {"inflation_radius": 0.6, "cost_scaling_factor": 1.0})
    assert after["inflation_radius"] == pytest.approx(0.6)
    graph.run(duration=2.5)
    assert inflated() > 1.5 * before  # 0.3 m → 0.6 m: about twice the band
    _set(probe, layer, {"enabled": False})
    graph.run(duration=2.5)
    assert inflated() == 0
