"""Debian's real ROS 1 tools and rospy against ``belvedere``'s master: the same commands print
the same as against Debian's own roscore, and messages, parameters and service calls cross
between ROS 1 programs and graph nodes both ways, value for value."""

from __future__ import annotations

import signal
import textwrap
import threading
import time
from functools import partial
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.ros1wire import MasterHandle
from tests.debian_ros import ROS_PYTHON
from tests.ros1wire.conftest import Ros1, publish_until, rospy_talker
from tests.waiting import DEADLINE, wait_until

pytestmark = pytest.mark.usefixtures("needs_debian_ros")

ROSPARAM_SEQUENCE: tuple[tuple[str, ...], ...] = (
    ("rosparam", "set", "/robot/speed", "0.5"),
    ("rosparam", "set", "/robot/name", "mbot"),
    ("rosparam", "set", "/robot/wheels", "[1, 2.5, x]"),
    ("rosparam", "set", "/robot/pid", "{p: 1.0, i: 0, d: 0.1}"),
    ("rosparam", "get", "/robot"),
    ("rosparam", "get", "/robot/speed"),
    ("rosparam", "get", "/robot/wheels"),
    ("rosparam", "list", "/robot"),
    ("rosparam", "delete", "/robot/name"),
    ("rosparam", "get", "/robot/name"),
    ("rosparam", "delete", "/robot/nothing"),
    ("rosparam", "get", "/robot/pid/p"),
    ("rosparam", "set", "/robot/pid", "{i: 2}"),
    ("rosparam", "get", "/robot/pid"),
    ("rosparam", "get", "/nothing/here"),
)


def _transcript(ros: Ros1) -> list[tuple[str, int, str, list[str]]]:
    out = []
    for cmd in ROSPARAM_SEQUENCE:
        r = ros.run(*cmd)
        out.append((" ".join(cmd), r.returncode, r.stdout, r.stderr.strip().splitlines()[-1:]))
    return out


def test_rosparam_prints_what_it_prints_against_debians_roscore(
    debian_roscore: Ros1, ros_graph: tuple[Graph, MasterHandle]
) -> None:
    ours = _transcript(Ros1(ros_graph[1].uri))
    theirs = _transcript(debian_roscore)
    assert ours == theirs


def test_parameters_set_by_rosparam_are_the_graphs(ros_graph: tuple[Graph, MasterHandle]) -> None:
    graph, handle = ros_graph
    ros = Ros1(handle.uri)
    graph.params.set("/move_base/controller_frequency", 5.0)
    assert ros.run("rosparam", "get", "/move_base/controller_frequency").stdout == "5.0\n"
    assert ros.run("rosparam", "set", "/amcl/max_particles", "2000").returncode == 0
    assert graph.params.get("/amcl/max_particles") == 2000


def test_a_rospy_talker_reaches_a_graph_subscriber_message_for_message(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    graph, handle = ros_graph
    heard: list[str] = []
    node = graph.create_node("listener")
    graph.executor.post(
        lambda: node.subscribe("/chatter", "std_msgs/String", lambda m: heard.append(m.data))
    )
    talker = Ros1(handle.uri).start(
        str(ROS_PYTHON), str(rospy_talker(tmp_path, "/chatter", 30, "hello"))
    )
    try:
        assert talker.wait(timeout=DEADLINE) == 0, talker.stderr.read() if talker.stderr else ""
    finally:
        talker.kill()
    wait_until(lambda: len(heard) >= 30, what="30 messages from rospy", detail=lambda: heard)
    assert heard == [f"hello {i}" for i in range(30)]


def test_rostopic_echo_hears_a_graph_publisher(ros_graph: tuple[Graph, MasterHandle]) -> None:
    graph, handle = ros_graph
    node = graph.create_node("odometry")
    pub = node.publisher("/odom", "nav_msgs/Odometry")
    echo = Ros1(handle.uri).start("rostopic", "echo", "-n", "2", "/odom/pose/pose/position")
    stop = threading.Event()

    def publish() -> None:
        x = 0.0
        while not stop.is_set():
            x += 0.25
            data = {"pose": {"pose": {"position": {"x": 1.5, "y": -2.0, "z": 0.0}}}}
            graph.executor.post(partial(pub.publish_data, data))
            time.sleep(0.05)

    threading.Thread(target=publish, daemon=True).start()
    try:
        out, err = echo.communicate(timeout=DEADLINE)
    finally:
        stop.set()
        echo.kill()
    assert out == "x: 1.5\ny: -2.0\nz: 0.0\n---\nx: 1.5\ny: -2.0\nz: 0.0\n---\n", err


def test_ros1_tools_see_the_graphs_nodes_topics_and_services(
    ros_graph: tuple[Graph, MasterHandle],
) -> None:
    graph, handle = ros_graph
    node = graph.create_node("mbot_driver")
    node.publisher("/cmd_vel_out", "geometry_msgs/Twist")
    node.subscribe("/cmd_vel", "geometry_msgs/Twist", lambda m: None)
    node.service("trigger", "std_srvs/Trigger", lambda req: {"success": True, "message": "done"})
    ros = Ros1(handle.uri)
    wait_until(
        lambda: "/trigger" in ros.run("rosservice", "list").stdout,
        what="the graph's service listed",
    )
    assert "/cmd_vel_out" in ros.run("rostopic", "list").stdout.split()
    assert "/mbot_driver" in ros.run("rosnode", "list").stdout.split()
    info = ros.run("rostopic", "info", "/cmd_vel").stdout
    assert "Type: geometry_msgs/Twist" in info
    assert " * /mbot_driver (" in info.split("Subscribers:")[1]
    assert ros.run("rosservice", "type", "/trigger").stdout == "std_srvs/Trigger\n"
    called = ros.run("rosservice", "call", "/trigger")
    assert called.stdout == 'success: True\nmessage: "done"\n', called.stderr


def test_rospy_calls_a_graph_service_and_a_failure_is_its_error(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    graph, handle = ros_graph
    node = graph.create_node("adder")

    def fail(req: Any) -> Any:
        msg = "no turtle here"
        raise ValueError(msg)

    node.service("spawn_nothing", "std_srvs/Empty", fail)
    node.service("set_flag", "std_srvs/SetBool", lambda r: {"success": r.data, "message": "ok"})
    script = tmp_path / "client.py"
    script.write_text(
        textwrap.dedent(
            """
            import rospy
            from std_srvs.srv import Empty, SetBool
            rospy.wait_for_service("/set_flag", timeout=20)
            flag = rospy.ServiceProxy("/set_flag", SetBool, persistent=True)
            print(flag(True).success, flag(False).success, flag(True).message)
            try:
                rospy.ServiceProxy("/spawn_nothing", Empty)()
            except rospy.ServiceException as err:
                print("failed:", err)
            """
        )
    )
    r = Ros1(handle.uri).run(str(ROS_PYTHON), str(script), timeout=DEADLINE)
    assert r.stdout.splitlines()[0] == "True False ok", r.stderr
    assert r.stdout.splitlines()[1].startswith("failed: service [/spawn_nothing] responded with")
    assert "no turtle here" in r.stdout.splitlines()[1]


def test_rosbag_records_a_graph_topic(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    graph, handle = ros_graph
    pub = graph.create_node("counter").publisher("/count", "std_msgs/Int32")
    bag = tmp_path / "count.bag"
    ros = Ros1(handle.uri)
    record = ros.start("rosbag", "record", "-O", str(bag), "--duration=3", "/count")
    publish_until(graph, pub, lambda: record.poll() is not None, lambda i: {"data": i})
    assert record.wait(timeout=DEADLINE) == 0, record.stderr.read() if record.stderr else ""
    read = ros.run(
        str(ROS_PYTHON),
        "-c",
        "import sys, rosbag\nfor _, m, _ in rosbag.Bag(sys.argv[1]).read_messages(): print(m.data)",
        str(bag),
    )
    values = [int(v) for v in read.stdout.split()]
    assert len(values) > 10, read.stderr
    assert values == list(range(values[0], values[0] + len(values)))


def test_a_late_rostopic_echo_gets_a_latched_graph_message(
    ros_graph: tuple[Graph, MasterHandle],
) -> None:
    graph, handle = ros_graph
    pub = graph.create_node("map_server").publisher("/map_name", "std_msgs/String", latch=True)
    graph.executor.post(partial(pub.publish_data, {"data": "cloister"}))
    time.sleep(0.5)
    echo = Ros1(handle.uri).run("rostopic", "echo", "-n", "1", "/map_name", timeout=DEADLINE)
    assert echo.stdout == 'data: "cloister"\n---\n', echo.stderr


def test_a_rospy_node_runs_in_the_graphs_simulated_time(
    endpoint: str, needs_debian_ros: None, tmp_path: Path
) -> None:
    """/use_sim_time and /clock carry over: rospy's clock is the simulation's."""
    from belvedere.graph import ZenohTransport
    from belvedere.ros1wire import start_master

    graph = Graph(sim_time=True, transport=ZenohTransport(endpoint=endpoint))
    graph.params.set("/use_sim_time", True)
    handle = start_master(graph, port=0)
    graph.start(rtf=1.0)
    script = tmp_path / "clock.py"
    script.write_text(
        "import rospy\n"
        "rospy.init_node('clock_reader')\n"
        "while rospy.Time.now().to_sec() == 0 and not rospy.is_shutdown():\n"
        "    rospy.sleep(0.01)\n"
        "print(rospy.Time.now().to_sec())\n"
    )
    try:
        r = Ros1(handle.uri).run(str(ROS_PYTHON), str(script), timeout=DEADLINE)
        seen = float(r.stdout.strip() or "nan")
        assert 0 < seen <= graph.now_ns() / 1e9 + 0.5, r.stderr
    finally:
        handle.close()
        graph.shutdown()


def test_a_rospy_node_that_ends_is_unregistered(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    """rospy unregisters its topics at its end in one ``system.multicall``."""
    graph, handle = ros_graph
    graph.create_node("listener").subscribe("/chatter", "std_msgs/String", lambda m: None)
    ros = Ros1(handle.uri)
    talker = ros.start(str(ROS_PYTHON), str(rospy_talker(tmp_path, "/chatter", 3, "bye")))
    assert talker.wait(timeout=DEADLINE) == 0
    wait_until(
        lambda: "ros1_talker" not in ros.run("rosnode", "list").stdout,
        what="the ended rospy node unregistered",
    )


def _bag_of_counts(ros: Ros1, bag: Path, count: int) -> None:
    """A bag Debian's rosbag writes: /count (std_msgs/Int32) 0 … count-1, 50 ms apart from
    t = 1000 s."""
    write = ros.run(
        str(ROS_PYTHON),
        "-c",
        textwrap.dedent(
            f"""
            import rosbag, rospy
            from std_msgs.msg import Int32
            with rosbag.Bag({str(bag)!r}, "w") as out:
                for i in range({count}):
                    out.write("/count", Int32(data=i), rospy.Time(1000 + 0.05 * i))
            """
        ),
    )
    assert write.returncode == 0, write.stderr


@pytest.mark.parametrize("busy", [False, True], ids=["idle", "busy_executor"])
def test_rosbag_play_reaches_a_graph_subscriber_in_order(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path, busy: bool
) -> None:
    """Every message of a played bag, in order. rosbag ends as soon as it has played: the
    master may say so before the bridge has published what it read (``busy``: the graph's
    executor is busy throughout the play), and that is still delivered."""
    graph, handle = ros_graph
    heard: list[int] = []
    graph.create_node("listener").subscribe(
        "/count", "std_msgs/Int32", lambda m: heard.append(m.data), queue_size=100
    )
    ros = Ros1(handle.uri)
    bag = tmp_path / "count.bag"
    _bag_of_counts(ros, bag, 40)
    if busy:
        graph.executor.post(lambda: time.sleep(4.0))  # busy while rosbag plays and ends
    play = ros.run(
        "rosbag", "play", "-q", "-r", "20", "--wait-for-subscribers", str(bag), timeout=DEADLINE
    )
    assert play.returncode == 0, play.stderr
    wait_until(
        lambda: len(heard) >= 40,
        what="the bag's 40 messages",
        timeout=DEADLINE,
        detail=lambda: heard,
    )
    assert heard == list(range(40))


def test_rosbag_play_clock_drives_a_graph_in_simulated_time(
    endpoint: str, needs_debian_ros: None, tmp_path: Path
) -> None:
    """``rosbag play --clock``: a graph that follows /clock runs in the bag's time, as a
    ROS 1 node with /use_sim_time does."""
    from belvedere.graph import ZenohTransport
    from belvedere.ros1wire import start_master

    graph = Graph(sim_time=True, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    graph.params.set("/use_sim_time", True)
    listener = graph.create_node("listener")
    graph.follow_clock(listener)
    stamps: list[tuple[int, int]] = []
    listener.subscribe(
        "/count",
        "std_msgs/Int32",
        lambda m: stamps.append((m.data, graph.now_ns())),
        queue_size=100,
    )
    graph.start(rtf=None)
    handle = start_master(graph, port=0)
    try:
        ros = Ros1(handle.uri)
        bag = tmp_path / "count.bag"
        _bag_of_counts(ros, bag, 40)
        play = ros.run(
            "rosbag", "play", "-q", "--clock", "--wait-for-subscribers", str(bag), timeout=DEADLINE
        )
        assert play.returncode == 0, play.stderr
        wait_until(lambda: len(stamps) >= 40, what="the bag's 40 messages", timeout=DEADLINE)
        assert [value for value, _ in stamps] == list(range(40))
        # each message is heard at its bag time (the clock runs at 100 Hz by default)
        for value, now in stamps:
            assert abs(now / 1e9 - (1000 + 0.05 * value)) < 0.1, (value, now)
    finally:
        handle.close()
        graph.shutdown()


def test_rostopic_hz_measures_a_graph_rate_in_simulated_time(
    endpoint: str, needs_debian_ros: None
) -> None:
    """rostopic hz takes its times from /clock under /use_sim_time: a 10 Hz timer of the
    simulation is 10 Hz to it, whatever the machine's load does to wall time."""
    from belvedere.graph import ZenohTransport
    from belvedere.ros1wire import start_master

    graph = Graph(sim_time=True, transport=ZenohTransport(endpoint=endpoint))
    graph.params.set("/use_sim_time", True)
    node = graph.create_node("ticker")
    pub = node.publisher("/tick", "std_msgs/Int32")
    node.timer(0.1, lambda: pub.publish_data({"data": 1}))
    graph.start(rtf=1.0)
    handle = start_master(graph, port=0)
    # unbuffered: rostopic prints a rate a second, into a pipe
    hz = Ros1(handle.uri).start(str(ROS_PYTHON), "-u", "/usr/bin/rostopic", "hz", "/tick")
    rates: list[float] = []
    try:
        assert hz.stdout is not None
        for line in hz.stdout:
            if "average rate:" in line:
                rates.append(float(line.split(":")[1]))
            if len(rates) >= 3:
                break
    finally:
        hz.terminate()
        hz.communicate(timeout=DEADLINE)
        handle.close()
        graph.shutdown()
    assert rates, "rostopic hz printed no rate"
    assert all(abs(rate - 10.0) < 0.5 for rate in rates[1:]), rates


def test_rosbag_record_keeps_a_graph_topics_latching(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    """The connection header says a latched graph topic latches: rosbag keeps the flag, and
    its play latches the topic again."""
    graph, handle = ros_graph
    node = graph.create_node("map_server")
    latched = node.publisher("/map_name", "std_msgs/String", latch=True)
    plain = node.publisher("/chatter", "std_msgs/String")
    graph.executor.post(partial(latched.publish_data, {"data": "cloister"}))
    ros = Ros1(handle.uri)
    bag = tmp_path / "latch.bag"
    record = ros.start("rosbag", "record", "-O", str(bag), "--duration=2", "/map_name", "/chatter")
    publish_until(graph, plain, lambda: record.poll() is not None, lambda i: {"data": str(i)})
    assert record.wait(timeout=DEADLINE) == 0
    read = ros.run(
        str(ROS_PYTHON),
        "-c",
        "import sys, rosbag\n"
        "for c in rosbag.Bag(sys.argv[1])._get_connections():\n"
        "    print(c.topic, c.header.get('latching').decode())",
        str(bag),
    )
    flags = dict(line.split() for line in read.stdout.splitlines())
    assert flags == {"/map_name": "1", "/chatter": "0"}, read.stderr


def test_rosnode_kill_shuts_a_graph_node_down(ros_graph: tuple[Graph, MasterHandle]) -> None:
    """Each graph node has its own slave URI, so rosnode kill (the slave API's shutdown)
    reaches that node alone, as ``belvedere node kill`` does."""
    graph, handle = ros_graph
    doomed = graph.create_node("doomed")
    doomed.publisher("/doomed_out", "std_msgs/Int32")
    graph.create_node("spared").publisher("/spared_out", "std_msgs/Int32")
    ros = Ros1(handle.uri)
    wait_until(
        lambda: {"/doomed", "/spared"} <= set(ros.run("rosnode", "list").stdout.split()),
        what="both graph nodes listed by rosnode",
    )
    info = ros.run("rosnode", "info", "/doomed").stdout
    assert "/doomed_out" in info, info
    assert "/spared_out" not in info, info
    kill = ros.run("rosnode", "kill", "/doomed")
    assert kill.returncode == 0, kill.stderr
    assert "killed" in kill.stdout, kill.stdout
    wait_until(
        lambda: "/doomed" not in ros.run("rosnode", "list").stdout.split(),
        what="the killed node to leave",
    )
    assert doomed.shutdown_request is not None
    assert doomed.shutdown_request[1] == "user request"
    assert "/spared" in ros.run("rosnode", "list").stdout.split()


def test_a_ros1_service_that_ends_is_withdrawn_from_the_graph(
    ros_graph: tuple[Graph, MasterHandle], tmp_path: Path
) -> None:
    graph, handle = ros_graph
    script = tmp_path / "flag_server.py"
    script.write_text(
        textwrap.dedent(
            """
            import rospy
            from std_srvs.srv import SetBool, SetBoolResponse
            rospy.init_node("flag_server")
            rospy.Service("/flag", SetBool, lambda req: SetBoolResponse(True, "ok"))
            rospy.spin()  # until the test ends it
            """
        )
    )
    server = Ros1(handle.uri).start(str(ROS_PYTHON), str(script))
    try:
        wait_until(lambda: "/flag" in graph.services, what="the ROS 1 service on the graph")
    finally:
        server.send_signal(signal.SIGINT)  # Ctrl-C: rospy unregisters, then ends
        server.communicate(timeout=DEADLINE)
    wait_until(lambda: "/flag" not in graph.services, what="the ended service withdrawn")
    # the bridge goes on looking: a graph topic published now still reaches ROS 1
    pub = graph.create_node("late").publisher("/late", "std_msgs/String", latch=True)
    graph.executor.post(partial(pub.publish_data, {"data": "still here"}))
    echo = Ros1(handle.uri).run("rostopic", "echo", "-n", "1", "/late", timeout=DEADLINE)
    assert echo.stdout == 'data: "still here"\n---\n', echo.stderr
