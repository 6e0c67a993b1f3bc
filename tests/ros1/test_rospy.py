"""belvedere's rospy, end to end: scripts run by ``belvedere run`` in processes of their own,
talking to each other and to belvedere's nodes over the test's own graph."""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
from pathlib import Path

BELVEDERE = [sys.executable, "-m", "belvedere"]
DEADLINE = 120
STAMP = re.compile(r"^\[(INFO|WARN|ERROR|FATAL|DEBUG)\] \[\d+\.\d{6}(, \d+\.\d{6})?\]: ", re.M)


def _script(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def _masked(text: str) -> str:
    return STAMP.sub(r"[\1] [T]: ", text)


def _run(*words: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*BELVEDERE, "run", *words],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
    )


SERVICES = """\
    import rospy
    from std_srvs.srv import Empty, SetBool, SetBoolResponse, Trigger

    rospy.init_node("srv")

    def handle(req):
        if req.data:
            raise ValueError("boom")
        return SetBoolResponse(True, "fine")

    rospy.Service("set", SetBool, handle)
    rospy.Service("trig", Trigger, lambda r: None)
    rospy.Service("empty", Empty, lambda r: [])
    rospy.wait_for_service("set", 2)
    p = rospy.ServiceProxy("set", SetBool)
    print(p(False).message, p(data=False).success)
    calls = (("set", SetBool, True), ("trig", Trigger, None), ("nope", Trigger, None))
    for name, cls, arg in calls:
        try:
            rospy.ServiceProxy(name, cls)(*([] if arg is None else [arg]))
        except rospy.ServiceException as e:
            print("SE", e)
    print(type(rospy.ServiceProxy("empty", Empty)()).__name__)
    try:
        rospy.wait_for_service("nope", 0.3)
    except rospy.ROSException as e:
        print("RE", e)
"""


def test_services_answer_and_fail_with_rospys_texts(tmp_path: Path) -> None:
    done = _run(str(_script(tmp_path, "srv.py", SERVICES)))
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "fine True",
        "SE service [/set] responded with an error: b'error processing request: boom'",
        "SE service [/trig] responded with an error: "
        "b'service cannot process request: service handler returned None'",
        "SE service [/nope] unavailable",
        "EmptyResponse",
        "RE timeout exceeded while waiting for service /nope",
    ]
    # the server logs the handler's error with its traceback, on stderr
    assert "[ERROR] [T]: Error processing request: boom\n" in _masked(done.stderr)
    assert 'raise ValueError("boom")' in done.stderr


PARAMS = """\
    import rospy

    rospy.init_node("params")
    for v in (1, 2.5, True, "s", [1, "a"], {"a": {"b": 1}}):
        rospy.set_param("~v", v)
        print(repr(rospy.get_param("~v")))
    for bad in (2**40, None, {1: 2}):
        try:
            rospy.set_param("x", bad)
        except (OverflowError, TypeError) as e:
            print(type(e).__name__, e)
    try:
        rospy.get_param("missing")
    except KeyError as e:
        print("KeyError", e)
    print(rospy.get_param("missing", 7), rospy.has_param("~v"), rospy.search_param("v"))
    print(rospy.get_param("~rate"), rospy.get_param("~label"))
    rospy.set_param("/a/b/c", 3)
    print(rospy.get_param("/a"), rospy.search_param("a/b"))
    rospy.delete_param("/a/b")
    print(rospy.get_param("/a"), "/a/b/c" in rospy.get_param_names())
    try:
        rospy.delete_param("/a/b")
    except KeyError as e:
        print("KeyError", e)
    print(rospy.get_name(), rospy.get_namespace(), end=" ")
    print(rospy.resolve_name("x"), rospy.resolve_name("~x"))
    print(rospy.resolve_name("chatter"), rospy.myargv())
"""


def test_parameters_follow_xmlrpc_rules_and_names_resolve(tmp_path: Path) -> None:
    script = _script(tmp_path, "params.py", PARAMS)
    done = _run(str(script), "one", "_rate:=10", "_label:=hi", "chatter:=/other", "__ns:=/robot")
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "1",
        "2.5",
        "True",
        "'s'",
        "[1, 'a']",
        "{'a': {'b': 1}}",
        "OverflowError int exceeds XML-RPC limits",
        "TypeError cannot marshal None unless allow_none is enabled",
        "TypeError dictionary key must be string",
        "KeyError 'missing'",
        "7 True /robot/params/v",
        "10 hi",
        "{'b': {'c': 3}} /a/b",
        "{} False",
        "KeyError '/a/b'",
        "/robot/params /robot/ /robot/x /robot/params/x",
        f"/other {[str(script), 'one']}",
    ]


TALKER = """\
    import rospy
    from geometry_msgs.msg import PointStamped
    from std_msgs.msg import Header, String

    rospy.init_node("talker")
    pub = rospy.Publisher("chatter", String, queue_size=10)
    stamped = rospy.Publisher("stamped", PointStamped, queue_size=10)
    rate = rospy.Rate(20)
    while not (pub.get_num_connections() and stamped.get_num_connections()):
        rate.sleep()
    for i in range(5):
        rospy.loginfo("hello %d", i)
        pub.publish("hello %d" % i)
        stamped.publish(PointStamped(header=Header(frame_id="f%d" % i)))
        rate.sleep()
    rospy.on_shutdown(lambda: print("talker: shutdown hook"))
"""

LISTENER = """\
    import threading

    import rospy
    from geometry_msgs.msg import PointStamped
    from std_msgs.msg import String

    heard, seqs = [], []
    lock = threading.Lock()

    def check():
        if len(heard) == 5 and len(seqs) == 5:
            rospy.signal_shutdown("heard enough")

    def on_chatter(msg, tag):
        with lock:
            heard.append(f"{tag} {msg.data}")
            check()

    def on_stamped(msg):
        with lock:
            seqs.append(f"seq {msg.header.seq} {msg.header.frame_id}")
            check()

    def report():
        print("\\n".join([*heard, *seqs, f"listener: done {len(heard)}"]), flush=True)

    rospy.init_node("listener")
    rospy.Subscriber("chatter", String, on_chatter, callback_args="heard:")
    rospy.Subscriber("stamped", PointStamped, on_stamped)
    rospy.on_shutdown(report)
    rospy.spin()
"""


def test_talker_and_listener_in_two_processes(tmp_path: Path) -> None:
    listener = subprocess.Popen(
        [*BELVEDERE, "run", "--rtf", "max", str(_script(tmp_path, "listener.py", LISTENER))],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert listener.stderr is not None
        assert "listening" in listener.stderr.readline()  # the graph is up
        talker = _run(str(_script(tmp_path, "talker.py", TALKER)))
        out, _ = listener.communicate(timeout=DEADLINE)
    finally:
        listener.kill()
    assert talker.returncode == 0, talker.stderr
    assert _masked(talker.stdout).splitlines() == [
        *(f"[INFO] [T]: hello {i}" for i in range(5)),
        "talker: shutdown hook",
    ]
    lines = out.splitlines()
    assert [line for line in lines if line.startswith("heard:")] == [
        f"heard: hello {i}" for i in range(5)
    ]
    # rospy numbers header.seq per publisher from 1
    assert [line for line in lines if line.startswith("seq")] == [
        f"seq {i + 1} f{i}" for i in range(5)
    ]
    assert lines[-1] == "listener: done 5"


PYTHON2 = """\
    #!/usr/bin/env python\r
    import rospy\r
    from geometry_msgs.msg import Twist\r
    rospy.init_node('teleop')\r
    pub = rospy.Publisher('/cmd_vel', Twist, queue_size=5)\r
    twist = Twist()\r
    twist.linear.x = 0.5\r
    print "speed %s" % twist.linear.x\r
    print rospy.get_name()\r
"""


def test_a_python_2_rospy_script_with_windows_line_ends_runs(tmp_path: Path) -> None:
    script = tmp_path / "teleop.py"
    script.write_bytes(textwrap.dedent(PYTHON2).encode())
    done = _run(str(script))
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["speed 0.5", "/teleop"]
    assert "a Python 2 script: running its Python 3 form" in done.stderr


def test_rospy_is_only_on_the_path_of_the_scripts_belvedere_runs() -> None:
    import importlib.util

    assert importlib.util.find_spec("rospy") is None
    assert importlib.util.find_spec("belvedere.ros1.rospy") is not None


LOGGER = """\
    import rospy

    rospy.init_node("logger")
    rospy.sleep(0.5)
    for i in range(3):
        rospy.loginfo("step %d", i)
        rospy.logwarn_once("only once")
        rospy.logerr_throttle(60, "throttled")
    rospy.logdebug("not shown at INFO")
"""


def test_log_lines_go_to_their_streams_and_to_rosout(tmp_path: Path, endpoint: str) -> None:
    from typing import Any

    from belvedere.graph import Graph, ZenohTransport
    from tests.conftest import EXAMPLES

    mbot = EXAMPLES / "mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
    host = subprocess.Popen(  # a simulation for the script to join
        [*BELVEDERE, "sim", str(mbot), "--headless"], stderr=subprocess.PIPE, text=True
    )
    assert host.stderr is not None
    line = host.stderr.readline()
    while line and "listening" not in line:  # after the model's warnings
        line = host.stderr.readline()
    assert "listening" in line
    logs: list[tuple[int, str, str]] = []
    watcher = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint, serve_params=False))

    def on_log(msg: Any) -> None:
        logs.append((msg.level, msg.name, msg.msg))

    watcher.create_node("watcher").subscribe("/rosout", "rosgraph_msgs/Log", on_log, queue_size=0)
    watcher.start(rtf=None)
    try:
        done = _run(str(_script(tmp_path, "logger.py", LOGGER)))
    finally:
        watcher.shutdown()
        host.terminate()
        host.wait(timeout=DEADLINE)
    assert done.returncode == 0, done.stderr
    assert _masked(done.stdout).splitlines() == [f"[INFO] [T]: step {i}" for i in range(3)]
    assert _masked(done.stderr).splitlines() == ["[WARN] [T]: only once", "[ERROR] [T]: throttled"]
    # in simulated time (the simulation sets /use_sim_time) the stamp shows both clocks
    assert re.search(r"^\[INFO\] \[\d+\.\d{6}, \d+\.\d{6}\]: step 0$", done.stdout, re.M)
    # the simulation's nodes log there too (robot_state_publisher: the placeholder wheels)
    assert (4, "/robot_state_publisher") in {(level, name) for level, name, _ in logs}
    assert [entry for entry in logs if entry[1] == "/logger"] == [
        (2, "/logger", "step 0"),
        (4, "/logger", "only once"),
        (8, "/logger", "throttled"),
        (2, "/logger", "step 1"),
        (2, "/logger", "step 2"),
    ]
