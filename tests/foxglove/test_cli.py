"""``--foxglove [PORT]`` on sim and launch, the ``belvedere foxglove`` verb beside a running
graph, and their errors: a port taken, a bad port, a bad origin."""

from __future__ import annotations

import socket
import subprocess
from pathlib import Path

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from belvedere.cli import main
from belvedere.graph import Graph, ZenohTransport
from tests.conftest import EXAMPLES
from tests.foxglove.client import FoxgloveClient
from tests.foxglove.test_bridge import plain, ros1_decoder
from tests.processes import BelvedereProcess

MBOT = str(EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro")
MBOT_YAML = str(EXAMPLES / "mbot_description/config/fake_mbot_arbotix.yaml")
HOUR_NS = 3600 * 1_000_000_000


class Served(BelvedereProcess):
    """``belvedere …`` in a process of its own, until it says where Foxglove connects."""

    def __init__(self, *args: str) -> None:
        super().__init__(
            list(args),
            ready="foxglove: ",
            ended="it ended before serving Foxglove",
            stdout=subprocess.DEVNULL,
        )
        self.url = self.ready.removeprefix("foxglove: ").strip()


@pytest.fixture
def noetic_twist() -> bytes:
    store = get_typestore(Stores.ROS1_NOETIC)
    twist = store.types["geometry_msgs/msg/Twist"]
    vector = store.types["geometry_msgs/msg/Vector3"]
    msg = twist(vector(0.2, 0.0, 0.0), vector(0.0, 0.0, 0.0))
    return bytes(store.serialize_ros1(msg, twist.__msgtype__))


def test_sim_serves_its_topics_and_takes_cmd_vel_from_foxglove(
    endpoint: str, noetic_twist: bytes
) -> None:
    served = Served("sim", MBOT, "--config", MBOT_YAML, "--headless", "--foxglove", "0")
    try:
        assert served.url.startswith("ws://127.0.0.1:")
        client = FoxgloveClient(served.url)
        odom = client.channel("/odom")
        assert odom["schemaName"] == "nav_msgs/Odometry"
        assert client.channel("/tf")["schemaName"] == "tf2_msgs/TFMessage"
        assert client.channel("/joint_states")["schemaName"] == "sensor_msgs/JointState"
        sub = client.subscribe("/odom")
        decode = ros1_decoder(odom)
        first = client.wait(lambda: client.received(sub), what="odometry")[0]
        stamp = plain(decode(first.data))["header"]["stamp"]
        # sent at the simulated time it was published at, which is its stamp
        assert first.log_time == stamp["sec"] * 1_000_000_000 + stamp["nanosec"]
        assert first.log_time < HOUR_NS
        # the Publish panel drives the robot
        cid = client.advertise("/cmd_vel", "ros1", "geometry_msgs/Twist")
        client.publish(cid, noetic_twist)

        def moving() -> bool:
            last = client.received(sub)[-1]
            return bool(plain(decode(last.data))["twist"]["twist"]["linear"]["x"] == 0.2)

        client.wait(moving, what="the odometry of a robot driven from Foxglove")
        client.close()
    finally:
        served.stop()


def test_display_serves_the_joint_states_its_sliders_publish(endpoint: str) -> None:
    """``belvedere display MODEL --foxglove 0``: the model's joint states and transforms
    (what its sliders and robot_state_publisher publish) reach Foxglove."""
    served = Served("display", MBOT, "--port", "0", "--foxglove", "0")
    try:
        client = FoxgloveClient(served.url)
        joints = client.channel("/joint_states")
        assert joints["schemaName"] == "sensor_msgs/JointState"
        assert client.channel("/tf_static")["schemaName"] == "tf2_msgs/TFMessage"
        sub = client.subscribe("/joint_states")
        decode = ros1_decoder(joints)
        first = client.wait(lambda: client.received(sub), what="joint states")[0]
        names = plain(decode(first.data))["name"]
        assert {"left_wheel_joint", "right_wheel_joint"} <= set(names)
        client.close()
    finally:
        served.stop()


def test_the_foxglove_verb_serves_a_running_simulation(endpoint: str) -> None:
    graph = Graph(sim_time=True, transport=ZenohTransport())
    node = graph.create_node("laser")
    scan = node.publisher("/scan", "sensor_msgs/LaserScan")
    count = [0]

    def send() -> None:
        count[0] += 1
        ranges = np.full(360, count[0], dtype=np.float32)
        scan.publish_data({"header": {"frame_id": "laser"}, "ranges": ranges.tolist()})

    node.timer(0.1, send)
    graph.start(rtf=2.0)
    served = Served("foxglove", "--port", "0")
    try:
        client = FoxgloveClient(served.url)
        channel = client.channel("/scan")
        assert (channel["encoding"], channel["schemaEncoding"]) == ("ros1", "ros1msg")
        sub = client.subscribe("/scan")
        client.wait(lambda: len(client.received(sub)) >= 3, what="three scans")
        decode = ros1_decoder(channel)
        scans = [plain(decode(m.data)) for m in client.received(sub)]
        beams = [s["ranges"][0] for s in scans]
        assert beams == list(range(int(beams[0]), int(beams[0]) + len(beams)))
        assert all(s["ranges"] == [s["ranges"][0]] * 360 for s in scans)
        # in the simulation's time (the bridge follows its /clock), never the wall clock's
        stamps = [m.log_time for m in client.received(sub)]
        assert stamps == sorted(stamps)
        assert 0 < stamps[-1] < HOUR_NS
        client.wait(lambda: client.times, what="the server's time")
        assert client.times[-1] < HOUR_NS
        # a publisher in another process that comes later, and goes
        later = graph.create_node("later").publisher("/later", "std_msgs/Int32")
        later_channel = client.channel("/later")
        assert later_channel["schemaName"] == "std_msgs/Int32"
        graph.executor.post(later.unregister)
        client.wait(lambda: later_channel["id"] in client.withdrawn, what="/later to go")
        client.close()
    finally:
        log = served.stop()
        graph.shutdown()
    assert "Traceback" not in log


def test_launch_serves_foxglove(
    endpoint: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    launch = tmp_path / "tf.launch"
    launch.write_text(
        """<launch>
          <node pkg="tf" type="static_transform_publisher" name="stp"
                args="1 0 0 0 0 0 map odom 100"/>
        </launch>"""
    )
    args = ["launch", str(launch), "--headless", "--rtf", "max", "--duration", "0.5"]
    assert main([*args, "--foxglove", "0"]) == 0
    assert "foxglove: ws://127.0.0.1:" in capsys.readouterr().err


def test_a_port_in_use_is_one_error(endpoint: str, capsys: pytest.CaptureFixture[str]) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        assert main(["foxglove", "--port", str(port), "--duration", "1"]) == 1
        err = capsys.readouterr().err
        (error,) = (line for line in err.splitlines() if "error" in line)
        assert error.startswith(f"error: cannot serve Foxglove on 127.0.0.1:{port}: ")
        assert "in use" in error
        assert "hint: choose another port: --foxglove PORT" in err
        assert "Traceback" not in err
        args = ["sim", MBOT, "--headless", "--rtf", "max", "--duration", "1"]
        assert main([*args, "--foxglove", str(port)]) == 1
        assert f"error: cannot serve Foxglove on 127.0.0.1:{port}: " in capsys.readouterr().err


def test_a_bad_port_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["sim", MBOT, "--foxglove", "70000"]) == 2
    assert "a port is a number from 0 to 65535 (0: any free port), not '70000'" in (
        capsys.readouterr().err
    )
