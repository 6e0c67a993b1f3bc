"""A second ``belvedere launch`` beside a running simulation, as the course runs its
navigation (the simulation in one terminal, amcl and move_base in another): a launch of
clients only joins the running graph and takes its clock, and the simulation's /clock goes on."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

from belvedere.graph import Graph, ZenohTransport, graph_running
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]
SIM = EXAMPLES / "mbot_description/launch/arbotix_mbot_with_laser_xacro.launch"


def test_a_launch_of_clients_joins_the_running_simulation(endpoint: str, tmp_path: Path) -> None:
    clients = tmp_path / "clients.launch"
    clients.write_text(
        "<launch>\n"
        '  <node pkg="tf" type="static_transform_publisher" name="map_to_odom"\n'
        '        args="0 0 0 0 0 0 map odom 100"/>\n'
        "</launch>\n"
    )
    sim = [*BELVEDERE, "launch", "--headless", "--rtf", "4", str(SIM)]
    probe = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    clock: list[float] = []
    stamps: list[float] = []

    def on_tf(msg: Any) -> None:
        for t in msg.transforms:
            if t.child_frame_id == "odom" and t.header.frame_id == "map":
                stamps.append(t.header.stamp.sec + t.header.stamp.nanosec / 1e9)

    node = probe.create_node("probe")
    node.subscribe("/clock", "rosgraph_msgs/Clock", lambda m: clock.append(m.clock.sec))
    node.subscribe("/tf_static", "tf2_msgs/TFMessage", on_tf)
    probe.start()
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    with subprocess.Popen(sim, **quiet) as running:  # type: ignore[call-overload]
        try:
            wait_until(lambda: graph_running() or running.poll() is not None, what="the graph")
            wait_until(lambda: clock and clock[-1] >= 8, what="8 s of the simulation's time")
            launch = [*BELVEDERE, "launch", "--headless", str(clients)]
            with subprocess.Popen(launch, **quiet) as second:  # type: ignore[call-overload]
                try:
                    since = len(clock)
                    wait_until(lambda: stamps, what="the joined launch's transform")
                    wait_until(
                        lambda: len(clock) > since + 20, what="the simulation's /clock going on"
                    )
                    # one clock, the simulation's: a launch of its own would announce its
                    # own time from 0 beside it (or, named alike, replace the simulation's)
                    after = clock[since:]
                    assert after == sorted(after)
                    assert min(after) >= 8
                    assert second.poll() is None
                    assert running.poll() is None
                finally:
                    second.terminate()
                    second.wait(timeout=DEADLINE)
        finally:
            running.terminate()
            running.wait(timeout=DEADLINE)
            probe.shutdown()


def test_spawn_model_beside_a_running_simulation(endpoint: str, tmp_path: Path) -> None:
    """``rosrun gazebo_ros spawn_model -file … -urdf -model …`` in a second terminal puts the
    robot into the simulation the first one runs, and exits; a second robot of that name is
    refused as Gazebo refuses it."""
    urdf = tmp_path / "mbot.urdf"
    xacro = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
    subprocess.run([*BELVEDERE, "xacro", str(xacro), "-o", str(urdf)], check=True)
    spawn = [*BELVEDERE, "run", "gazebo_ros", "spawn_model", "-file", str(urdf), "-urdf"]
    alone = subprocess.run([*spawn, "-model", "mbot"], capture_output=True, text=True)
    assert alone.returncode == 1
    assert "spawn_model: no simulation is running" in alone.stderr
    probe = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint))
    models: list[list[str]] = []
    probe.create_node("probe").subscribe(
        "/gazebo/model_states", "gazebo_msgs/ModelStates", lambda m: models.append(list(m.name))
    )
    probe.start()
    world = [*BELVEDERE, "launch", "--headless", "gazebo_ros", "empty_world.launch"]
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    with subprocess.Popen(world, **quiet) as running:  # type: ignore[call-overload]
        try:
            wait_until(lambda: models or running.poll() is not None, what="the empty world")
            first = subprocess.run([*spawn, "-model", "mbot", "-x", "1"], capture_output=True)
            assert first.returncode == 0, first.stderr
            wait_until(lambda: "mbot" in models[-1], what="mbot in /gazebo/model_states")
            again = subprocess.run([*spawn, "-model", "mbot"], capture_output=True, text=True)
            assert again.returncode == 1
            assert "SpawnModel: Failure - model name mbot already exist." in again.stderr
            assert "error: spawn_model mbot:" in again.stderr
            assert running.poll() is None
        finally:
            running.terminate()
            running.wait(timeout=DEADLINE)
            probe.shutdown()
