"""The graph tools in separate processes, as a user runs them in two terminals."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from belvedere.cli import main
from belvedere.graph import Graph, ZenohTransport
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere"]
SEED = "{linear: {x: 0.2, y: 0, z: 0}, angular: {x: 0, y: 0, z: 0.5}}"
WAIT = str(DEADLINE / 2)
"""--timeout for a tool that should get what it waits for (it may wait twice: for the topic
to appear, then for a message)."""


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*BELVEDERE, *args], capture_output=True, text=True, timeout=2 * DEADLINE, check=False
    )


def _popen(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [*BELVEDERE, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )


def _finish(proc: subprocess.Popen[str]) -> tuple[str, str]:
    """What a tool printed once it ended by itself (killed and failed if it does not)."""
    try:
        return proc.communicate(timeout=DEADLINE)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        msg = f"{proc.args!r} did not end within {DEADLINE:g} s; stdout {out!r}, stderr {err!r}"
        raise AssertionError(msg) from None


def _pub_to_echo(
    endpoint: str, echo_args: list[str], msg_type: str, *pub_args: str
) -> tuple[subprocess.CompletedProcess[str], subprocess.Popen[str], str, str]:
    """``topic pub`` to a ``topic echo`` running in another process; what both printed."""
    topic = echo_args[0]
    echo = _popen("topic", "echo", *echo_args)
    # A publisher that never publishes shows echo the topic's type; once echo's subscription
    # reaches it, pub (started after) finds echo there too.
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    try:
        typed = graph.create_node("typed").publisher(topic, msg_type)
        graph.start(rtf=None)
        wait_until(lambda: typed.topic.remote, what=f"topic echo to subscribe to {topic}")
        pub = run("topic", "pub", topic, msg_type, *pub_args)
        out, err = _finish(echo)
    finally:
        if echo.poll() is None:
            echo.kill()
        graph.shutdown()
    return pub, echo, out, err


def test_echo_and_pub_find_each_other_without_a_central_process(endpoint: str) -> None:
    pub, echo, out, err = _pub_to_echo(
        endpoint, ["/chatter", "-n", "2"], "std_msgs/String", "data: hi", "-r", "5", "--count", "6"
    )
    assert pub.returncode == 0, pub.stderr
    assert echo.returncode == 0, err
    assert out == 'data: "hi"\n---\ndata: "hi"\n---\n'


def test_the_seeds_command_against_a_running_graph(peer: Any) -> None:
    echo = _popen("topic", "echo", "/cmd_echo", "-n", "1")
    pub = _popen("topic", "pub", "-r", "10", "/cmd_vel", "geometry_msgs/Twist", SEED)
    try:
        out, err = _finish(echo)
    finally:
        pub.terminate()
        pub.wait(timeout=DEADLINE)
    assert echo.returncode == 0, err
    assert out.startswith("linear: \n  x: 0.2\n")
    assert "angular: \n  x: 0.0\n  y: 0.0\n  z: 0.5\n---\n" in out


def test_introspection_params_and_services(peer: Any, tmp_path: Path) -> None:
    listing = run("topic", "list", "-t")
    assert "/chatter [std_msgs/String]" in listing.stdout
    assert run("topic", "type", "/chatter").stdout == "std_msgs/String\n"
    info = run("topic", "info", "/chatter").stdout
    assert "Type: std_msgs/String" in info
    assert " * /peer" in info
    assert "/peer" in run("node", "list").stdout.split()
    node_info = run("node", "info", "/peer").stdout
    assert " * /chatter [std_msgs/String]" in node_info
    assert " * /trigger [std_srvs/Trigger]" in node_info
    assert run("param", "get", "/robot/speed").stdout == "0.5\n"
    assert run("param", "set", "/robot/mode", "{a: 1}").returncode == 0
    assert run("param", "get", "/robot/mode/a").stdout == "1\n"
    assert "/robot/mode/a" in run("param", "list").stdout.split()
    params = tmp_path / "p.yaml"
    params.write_text("gains: {kp: 2.0}\n")
    assert run("param", "load", str(params), "/ctrl").returncode == 0
    assert run("param", "get", "/ctrl/gains/kp").stdout == "2.0\n"
    dump = tmp_path / "dump.yaml"
    assert run("param", "dump", str(dump)).returncode == 0
    assert "kp: 2.0" in dump.read_text()
    assert run("param", "delete", "/ctrl").returncode == 0
    missing = run("param", "get", "/ctrl/gains/kp")
    assert missing.returncode == 1
    assert "is not set" in missing.stderr
    assert run("service", "list").stdout.split() == ["/trigger"]
    called = run("service", "call", "/trigger")
    assert called.stdout == 'success: True\nmessage: "done"\n'


def test_publishing_another_type_than_the_graphs_is_refused(peer: Any) -> None:
    """The issue's command against a node that subscribes to /cmd_vel as a Twist: one error
    naming both types, nothing sent."""
    pub = run("topic", "pub", "-r", "10", "/cmd_vel", "std_msgs/String", "hi")
    assert pub.returncode == 1
    assert pub.stdout == ""
    assert pub.stderr.splitlines()[-1] == (
        "error: topic /cmd_vel has type geometry_msgs/Twist (/peer subscribes to it); "
        "cannot publish std_msgs/String on it"
    )


def test_param_dump_on_a_full_disk_keeps_the_old_file(peer: Any, full_disk: Path) -> None:
    dump = full_disk / "params.yaml"
    dump.write_text("previous: 1\n")
    assert run("param", "set", "/big", "x" * 70_000).returncode == 0  # more than the disk holds
    result = run("param", "dump", str(dump))
    assert result.returncode == 1
    assert result.stderr.splitlines()[-1] == (
        f"error: cannot write {dump}: No space left on device; {dump} is unchanged"
    )
    assert dump.read_text() == "previous: 1\n"
    assert sorted(p.name for p in full_disk.iterdir()) == ["params.yaml"]


def test_absent_things_are_said_plainly(endpoint: str) -> None:
    echo = run("topic", "echo", "/nobody", "--timeout", "1")
    assert echo.returncode == 1
    assert "no node publishes or subscribes to /nobody (waited 1 s)" in echo.stderr
    call = run("service", "call", "/nothing")
    assert call.returncode == 1
    assert "service /nothing is not offered by any node" in call.stderr
    param = run("param", "get", "/x")
    assert param.returncode == 1
    assert "no running graph holds parameters" in param.stderr
    bad = run("topic", "pub", "/t", "geometry_msgs/Twist", "{linear: {w: 1}}", "-1")
    assert bad.returncode == 1
    assert "field 'linear.w' does not exist in geometry_msgs/Vector3" in bad.stderr


def test_example_talker_reaches_other_processes(endpoint: str) -> None:
    talker = subprocess.Popen(
        [sys.executable, str(Path(__file__).parents[2] / "examples" / "graph" / "talker.py")],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        echo = run("topic", "echo", "/chatter", "-n", "1", "--timeout", WAIT)
        assert talker.stdout is not None
        # (the echo can be done before the talker has logged what it said)
        out = talker.stdout.readline()
    finally:
        talker.terminate()
        talker.communicate(timeout=DEADLINE)
    assert echo.returncode == 0, echo.stderr
    assert echo.stdout.startswith('data: "hello world ')
    # its node.logger.info, as a ROS node prints it
    assert re.match(r"\[INFO\] \[\d+\.\d{6}\]: said hello world 1\n", out)


def test_tf_echo_and_tree(peer: Any) -> None:
    echo = run("tf", "echo", "base_link", "camera", "-n", "1", "--timeout", WAIT)
    assert echo.returncode == 0, echo.stderr
    assert echo.stdout.startswith("- Translation: [0.100, 0.000, 0.200]\n")
    assert "in RPY (degree) [0.000, 0.000, 90.000]" in echo.stdout
    # tree listens for a window (view_frames' 5 s) and shows what came: the latched transform
    tree = run("tf", "tree", "--wait", "5")
    assert tree.stdout == "base_link\n  camera [static]\n"
    missing = run("tf", "echo", "base_link", "nowhere", "--timeout", "1")
    assert missing.returncode == 1
    assert '"nowhere" passed to lookupTransform argument source_frame does not exist.' in (
        missing.stderr
    )
    assert "hint: the frames known: base_link, camera" in missing.stderr


@pytest.mark.parametrize(
    ("msg_type", "value", "error"),
    [
        (
            "std_msgs/Float32",
            "9" * 321,
            "field 'data': a 321-digit integer does not fit float32 (±3.4028235e+38)",
        ),
        (
            "std_msgs/Time",
            "9" * 321,
            "field 'data': a 321-digit integer does not fit a time (0 to 2147483647 s: int32 "
            "seconds on the wire)",
        ),
        (
            "std_msgs/Float32",
            "1.0e+300",
            "field 'data': 1e+300 does not fit float32 (±3.4028235e+38)",
        ),
    ],
)
def test_values_that_do_not_fit_stop_at_the_publisher(
    endpoint: str, capsys: pytest.CaptureFixture[str], msg_type: str, value: str, error: str
) -> None:
    # A subscriber in another process: what it would have received must be serialized.
    echo = subprocess.Popen(
        [*BELVEDERE, "topic", "echo", "/t", "-n", "1"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert main(["topic", "pub", "-1", "/t", msg_type, value]) == 1
        # after the line naming the graph it joined
        assert capsys.readouterr().err.splitlines()[-1] == f"error: {error}"
    finally:
        echo.kill()
        out, err = echo.communicate(timeout=10)
    assert out == ""
    assert "Traceback" not in err


def test_a_duration_with_negative_nanoseconds_reaches_another_process(endpoint: str) -> None:
    pub, _, out, err = _pub_to_echo(
        endpoint, ["/d", "-n", "1"], "std_msgs/Duration", "{data: {secs: 1, nsecs: -1}}", "-1"
    )
    assert pub.returncode == 0, pub.stderr
    assert out == "data: \n  secs: 0\n  nsecs: 999999999\n---\n", err


def test_tf_tree_in_a_simulation_counts_age_in_its_time(endpoint: str) -> None:
    """A simulation's transforms are stamped in its time: "s ago" counts in it too (against
    the wall clock they were 1.8e9 s old)."""
    from belvedere.description.urdf import RobotModel
    from belvedere.sim.kinematic import KinematicSimulation
    from tests.conftest import EXAMPLES

    graph = Graph(transport=ZenohTransport(endpoint=endpoint))
    model = RobotModel.from_path(EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro")
    KinematicSimulation(graph, model)
    graph.start(rtf=1.0)
    try:
        tree = run("tf", "tree", "--wait", "2")
    finally:
        graph.shutdown()
    assert tree.returncode == 0, tree.stderr
    ages = [float(a) for a in re.findall(r", ([0-9.]+) s ago", tree.stdout)]
    assert ages, tree.stdout
    assert max(ages) < 1.0, tree.stdout


LOGGING_NODES = """
from belvedere.graph import Graph, ZenohTransport

graph = Graph(sim_time=False, transport=ZenohTransport())
chatty = graph.create_node("chatty")
quiet = graph.create_node("quiet")
count = [0]


def tick():
    count[0] += 1
    chatty.logger.info("info %d", count[0])
    chatty.logger.warning("warn %d", count[0])
    quiet.logger.error("error %d", count[0])


chatty.timer(0.05, tick)
print("READY", flush=True)
graph.run()
"""


def test_log_shows_what_nodes_log_with_level_and_node_filters(
    endpoint: str, tmp_path: Path
) -> None:
    script = tmp_path / "logging_nodes.py"
    script.write_text(LOGGING_NODES)
    nodes = subprocess.Popen(
        [sys.executable, str(script)], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True
    )
    try:
        assert nodes.stdout is not None
        assert nodes.stdout.readline() == "READY\n"
        warnings = run("log", "--level", "warn", "--node", "chatty", "-n", "3")
        every = run("log", "-n", "9")
        verbose = run("log", "-v", "--node", "/quiet", "-n", "1")
        misspelt = run("log", "--node", "chaty", "--timeout", "1")
    finally:
        nodes.terminate()
        nodes.wait(timeout=DEADLINE)
    assert warnings.returncode == 0, warnings.stderr
    lines = warnings.stdout.splitlines()
    assert len(lines) == 3
    for line in lines:
        assert re.fullmatch(r"\[ WARN  \] \[/chatty\] \[\d+\.\d{6}\]: warn \d+", line), line
    shown = {tuple(line.split("]")[:2]) for line in every.stdout.splitlines()}
    assert shown == {("[ INFO  ", " [/chatty"), ("[ WARN  ", " [/chatty"), ("[ ERROR ", " [/quiet")}
    first, where = verbose.stdout.splitlines()
    assert re.fullmatch(r"\[ ERROR \] \[/quiet\] \[\d+\.\d{6}\]: error \d+", first)
    assert where == f"          [tick] {script}:14"
    assert misspelt.stderr.splitlines()[-3:] == [
        "warning: no node /chaty on the graph (yet); did you mean /chatty?",
        "error: no log message within 1 s",
        "  hint: is a node running and logging?",
    ]


def test_misspelt_names_get_the_graphs_closest(endpoint: str) -> None:
    """The issue's misspellings: a service, a node and a topic, each answered with the
    graph's names closest to it."""
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))
    gazebo = graph.create_node("gazebo")
    for name in ("/gazebo/reset_simulation", "/gazebo/reset_world"):
        gazebo.service(name, "std_srvs/Empty", lambda req: None)
    rsp = graph.create_node("robot_state_publisher")
    rsp.subscribe("/joint_states", "sensor_msgs/JointState", lambda msg: None)
    rsp.publisher("/tf", "tf2_msgs/TFMessage")
    graph.start(rtf=None)
    try:
        service = run("service", "call", "/gazebo/reset_simulaton")
        node = run("node", "info", "/robot_state_publishr")
        echo = run("topic", "echo", "/joint_state", "--timeout", "1")
        info = run("topic", "info", "/joint_state")
        waiting = _popen("topic", "echo", "/joint_state")
        try:
            assert waiting.stderr is not None
            line = waiting.stderr.readline()
            while line.startswith("graph: "):
                line = waiting.stderr.readline()
        finally:
            waiting.kill()
            waiting.communicate()
        far = run("service", "call", "/nothing_like_it")
    finally:
        graph.shutdown()
    assert service.returncode == node.returncode == echo.returncode == info.returncode == 1
    assert service.stderr.splitlines()[-2:] == [
        "error: service /gazebo/reset_simulaton is not offered by any node",
        "  hint: did you mean /gazebo/reset_simulation or /gazebo/reset_world?",
    ]
    assert node.stderr.splitlines()[-2:] == [
        "error: unknown node /robot_state_publishr",
        "  hint: did you mean /robot_state_publisher?",
    ]
    assert echo.stderr.splitlines()[-2:] == [
        "error: no node publishes or subscribes to /joint_state (waited 1 s)",
        "  hint: did you mean /joint_states?",
    ]
    assert info.stderr.splitlines()[-2:] == [
        "error: unknown topic /joint_state: no node publishes or subscribes to it",
        "  hint: did you mean /joint_states?",
    ]
    assert (
        line == "waiting for /joint_state to appear (Ctrl-C to stop); did you mean /joint_states?\n"
    )
    assert far.stderr.splitlines()[-2:] == [
        "error: service /nothing_like_it is not offered by any node",
        "  hint: see 'belvedere service list'",
    ]


def test_echo_of_a_misspelt_topic_in_a_run(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        ["run", "--rtf", "max", "--duration", "0.1", "--echo", "/tf_statc", "--headless",
         "tf2_ros", "static_transform_publisher", "1", "2", "3", "0", "0", "0", "map", "odom"]
    )  # fmt: skip
    assert code == 1
    assert capsys.readouterr().err.splitlines()[-2:] == [
        "error: --echo /tf_statc: no node in this run publishes or subscribes to it",
        "  hint: did you mean /tf_static?",
    ]
