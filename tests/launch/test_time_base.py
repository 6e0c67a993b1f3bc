"""One time base across processes, as ROS 1 has one master clock: the course's two-terminal
flows (a simulation in one process; navigation, scripts and tools each in their own) agree on
every stamp, every ``now()`` and every transform lookup.

The rule: a launch simulates time, so its graph publishes ``/clock`` and ``/use_sim_time`` is
true before any node starts (a launch's own ``/use_sim_time false`` is one warning); every
process that joins (a launch of clients, ``run`` of a node or a script, rospy, the tools)
follows that ``/clock``. A graph has one clock: a second simulation is refused.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from belvedere.bags import Decoder, open_bag
from belvedere.graph import NS, Graph, ZenohTransport
from belvedere.maps import OCCUPIED, load_map
from tests.conftest import EXAMPLES
from tests.waiting import DEADLINE, wait_until

BELVEDERE = [sys.executable, "-m", "belvedere", "--package-path", str(EXAMPLES)]
FAKE_TURTLEBOT = ["rbx1_bringup", "fake_turtlebot.launch"]
MBOT_ARBOTIX = ["mbot_description", "arbotix_mbot_with_laser_xacro.launch"]

SAME_BASE = 1.0
"""How far a receiver's now() may be from a message's stamp when both keep one time base.
On an idle machine it is one update (0.05 s for /odom, 0.1 s for /joint_states) and one
/clock tick (0.01 s); on a busy one a message or a /clock tick arrives late, so the
tests allow a second. A wrong base is off by the epoch (1.8e9 s) or by the run's age."""

STAMPS_SCRIPT = """\
import sys
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

# For each topic: how far each stamp is from this process's now() when it arrives.
seen = {}


def check(topic, skip=()):
    def received(msg):
        now = rospy.Time.now()
        if now.is_zero():
            return  # /clock not heard yet
        if hasattr(msg, "transforms"):
            stamps = [t.header.stamp for t in msg.transforms if t.child_frame_id not in skip]
        else:
            stamps = [msg.header.stamp]
        for stamp in stamps:
            seen.setdefault(topic, []).append((now - stamp).to_sec())

    return received


rospy.init_node("stamps")
rospy.Subscriber("/odom", Odometry, check("/odom"))
rospy.Subscriber("/joint_states", JointState, check("/joint_states"))
# fake_localization stamps map -> odom ahead by its transform_tolerance, as the original
rospy.Subscriber("/tf", TFMessage, check("/tf", skip=("odom",)))
print("use_sim_time", rospy.get_param("/use_sim_time"), flush=True)
rospy.sleep(float(sys.argv[1]))
for topic, lags in sorted(seen.items()):
    print(f"{topic} {len(lags)} {min(lags):.6f} {max(lags):.6f}", flush=True)
"""


@contextmanager
def running(command: list[str], log: Path) -> Iterator[subprocess.Popen[bytes]]:
    """``command`` running in its own process (a terminal of the course), its output in
    ``log``; ended when the block ends."""
    with log.open("wb") as out, subprocess.Popen(command, stdout=out, stderr=out) as process:
        try:
            yield process
        finally:
            process.terminate()
            try:
                process.wait(timeout=DEADLINE)
            except subprocess.TimeoutExpired:
                process.kill()


class Probe:
    """The test's own process on the graph, in the simulation's time (following /clock):
    the last /clock, and every /odom with this process's now() when it arrived."""

    def __init__(self, endpoint: str) -> None:
        # a tool's way: it holds no parameters (the graph's first launch does)
        transport = ZenohTransport(endpoint=endpoint, serve_params=False)
        self.graph = Graph(sim_time=True, transport=transport, clock_hz=None)
        node = self.graph.create_node("time_probe")
        self.clock: list[int] = []
        self.odom: list[tuple[int, int, Any]] = []
        node.subscribe("/clock", "rosgraph_msgs/Clock", self._on_clock, queue_size=1)
        self.graph.follow_clock(node)
        node.subscribe("/odom", "nav_msgs/Odometry", self._on_odom, queue_size=100)
        self.graph.start()

    def _on_clock(self, msg: Any) -> None:
        self.clock.append(msg.clock.sec * NS + msg.clock.nanosec)

    def _on_odom(self, msg: Any) -> None:
        now = self.graph.now_ns()
        if now == 0:
            return  # /clock not heard yet: this process has no time to compare with
        stamp = msg.header.stamp.sec * NS + msg.header.stamp.nanosec
        self.odom.append((now, stamp, msg.pose.pose.position))

    def at(self, x: float, y: float, within: float) -> bool:
        if not self.odom:
            return False
        p = self.odom[-1][2]
        return math.hypot(p.x - x, p.y - y) < within

    def worst_lag(self) -> float:
        """The largest |now() - stamp| of the /odom this process received, in seconds."""
        return max(abs(now - stamp) for now, stamp, _ in self.odom) / NS

    def close(self) -> None:
        self.graph.shutdown()


@contextmanager
def probing(endpoint: str) -> Iterator[Probe]:
    probe = Probe(endpoint)
    try:
        yield probe
    finally:
        probe.close()


def tool(*words: str) -> subprocess.CompletedProcess[str]:
    """A belvedere verb run to its end (one more terminal)."""
    return subprocess.run(
        [*BELVEDERE, *words], capture_output=True, text=True, timeout=DEADLINE, check=False
    )


def lags(output: str) -> dict[str, tuple[int, float, float]]:
    """The stamp checker's lines: topic → (messages, least and greatest now() - stamp)."""
    found = re.findall(r"^(/\S+) (\d+) (-?[0-9.]+) (-?[0-9.]+)$", output, re.MULTILINE)
    return {t: (int(n), float(lo), float(hi)) for t, n, lo, hi in found}


def offsets(echo: str, count: int) -> list[float]:
    """``topic echo --offset``'s offsets (each message's now() - stamp); ``count`` of them."""
    found = [float(v) for v in re.findall(r"^offset: (-?[0-9.e+-]+)$", echo, re.MULTILINE)]
    assert len(found) == count, echo
    return found


def test_fake_turtlebot_and_move_base_in_two_terminals(endpoint: str, tmp_path: Path) -> None:
    """rbx1's chapter: fake_turtlebot.launch in one terminal (its /use_sim_time false is
    overruled, saying so), fake_move_base_blank_map.launch in another, goals from a rospy
    script run in a third; the robot's /odom arrives; the tools join in its time."""
    with (
        probing(endpoint) as probe,
        running(
            [*BELVEDERE, "launch", "--headless", "--rtf", "1", *FAKE_TURTLEBOT],
            tmp_path / "sim.log",
        ) as sim,
    ):
        wait_until(lambda: probe.clock or sim.poll() is not None, what="the simulation's /clock")
        assert sim.poll() is None, (tmp_path / "sim.log").read_text()
        nav = [*BELVEDERE, "launch", "--headless", "rbx1_nav", "fake_move_base_blank_map.launch"]
        with running(nav, tmp_path / "nav.log") as second:
            goals = tool("run", "rbx1_nav", "nav_goals.py", "_goals:=[[1.0, 0.5, 0.0]]")
            assert "Goal ended: SUCCEEDED" in goals.stdout + goals.stderr, goals.stderr[-2000:]
            assert goals.returncode == 0
            wait_until(lambda: probe.at(1.0, 0.5, 0.25), what="/odom at the goal")
            # the tools, each in a process of its own, in the simulation's time
            echo = tool("topic", "echo", "--offset", "-n", "5", "/odom")
            assert echo.returncode == 0, echo.stderr
            assert all(abs(o) <= SAME_BASE for o in offsets(echo.stdout, 5)), echo.stdout
            tf = tool("tf", "echo", "map", "base_footprint", "-n", "1")
            x, y = (float(v) for v in re.findall(r"Translation: \[(\S+), (\S+),", tf.stdout)[0])
            assert math.hypot(x - 1.0, y - 0.5) < 0.25, tf.stdout + tf.stderr
            saved = tool("run", "map_server", "map_saver", "-f", str(tmp_path / "blank"))
            assert saved.returncode == 0, saved.stderr
            assert (tmp_path / "blank.yaml").is_file()
            bag = tmp_path / "odom.bag"
            recorded = tool("bag", "record", "-q", "--duration", "1", "-O", str(bag), "/odom")
            assert recorded.returncode == 0, recorded.stderr
            assert second.poll() is None
            assert sim.poll() is None
    sim_log = (tmp_path / "sim.log").read_text()
    nav_log = (tmp_path / "nav.log").read_text()
    assert re.search(
        r"fake_turtlebot\.launch:2:\d+: /use_sim_time false is not used: this launch simulates"
        r" time",
        sim_log,
    ), sim_log
    assert sim_log.count("/use_sim_time false is not used") == 1
    assert "transform timeout" not in nav_log, nav_log[-2000:]
    assert probe.worst_lag() <= SAME_BASE
    # rosbag's time of each message is the simulation's, as is its header's stamp
    opened = open_bag(bag)
    try:
        decoder = Decoder()
        records = [(m.stamp_ns, decoder.decode(m).header.stamp) for m in opened.messages()]
    finally:
        opened.close()
    assert records
    for stamp_ns, header in records:
        assert abs(stamp_ns - (header.sec * NS + header.nanosec)) / NS <= SAME_BASE


FAKE_NAV_DEMO = """\
<launch>
  <!-- the book's fake_nav_demo.launch, for the mbot: its own /use_sim_time false -->
  <param name="use_sim_time" value="false"/>
  <node name="map_server" pkg="map_server" type="map_server"
        args="$(find rbx1_nav)/maps/blank_map.yaml"/>
  <include file="$(find mbot_navigation)/launch/move_base.launch"/>
  <node pkg="fake_localization" type="fake_localization" name="fake_localization">
    <remap from="base_pose_ground_truth" to="odom"/>
  </node>
</launch>
"""

GOAL = (
    "{header: {frame_id: map, stamp: now}, "
    "pose: {position: {x: 0.6, y: -0.3}, orientation: {w: 1.0}}}"
)


def test_mbot_arbotix_and_a_nav_demo_in_two_terminals(endpoint: str, tmp_path: Path) -> None:
    """The mbot ArbotiX-with-laser launch in one terminal, a generated fake_nav_demo.launch
    (map_server, move_base, fake_localization) in another, a 2D Nav Goal stamped "now" from
    ``topic pub`` in a third, and a rospy script in a fourth: every message each receives is
    within one update period of its own now()."""
    demo = tmp_path / "fake_nav_demo.launch"
    demo.write_text(FAKE_NAV_DEMO)
    checker = tmp_path / "stamps.py"
    checker.write_text(STAMPS_SCRIPT)
    sim_log, nav_log = tmp_path / "sim.log", tmp_path / "nav.log"
    with (
        probing(endpoint) as probe,
        running([*BELVEDERE, "launch", "--headless", "--rtf", "1", *MBOT_ARBOTIX], sim_log) as sim,
    ):
        wait_until(lambda: probe.clock or sim.poll() is not None, what="the simulation's /clock")
        assert sim.poll() is None, sim_log.read_text()
        with running([*BELVEDERE, "launch", "--headless", str(demo)], nav_log) as second:
            wait_until(
                lambda: "process[fake_localization-3]" in nav_log.read_text(),
                what="the navigation launch",
            )
            goal = tool(
                "topic", "pub", "-1", "/move_base_simple/goal", "geometry_msgs/PoseStamped", GOAL
            )
            assert goal.returncode == 0, goal.stderr
            stamps = tool("run", str(checker), "2.0")
            assert stamps.returncode == 0, stamps.stderr
            wait_until(lambda: probe.at(0.6, -0.3, 0.2), what="/odom at the goal")
            assert second.poll() is None
            assert sim.poll() is None
    assert "use_sim_time True" in stamps.stdout
    seen = lags(stamps.stdout)
    assert set(seen) == {"/odom", "/joint_states", "/tf"}, stamps.stdout
    for topic, (count, least, most) in seen.items():
        assert count > 0
        # the stamp is this process's now(), give or take a late message (SAME_BASE)
        assert -SAME_BASE <= least <= most <= SAME_BASE, (topic, least, most)
    assert probe.worst_lag() <= SAME_BASE
    said = nav_log.read_text()
    assert re.search(
        r"fake_nav_demo\.launch:3:\d+: /use_sim_time false is not used: the running graph "
        r"simulates time",
        said,
    ), said
    assert "transform timeout" not in said


def test_a_second_simulation_is_refused_naming_the_first(endpoint: str, tmp_path: Path) -> None:
    """A user starting the simulation twice: the graph has one clock, so the second refuses
    to start (naming the process that runs the first), and /clock never jumps back."""
    with (
        probing(endpoint) as probe,
        running([*BELVEDERE, "launch", "--headless", *FAKE_TURTLEBOT], tmp_path / "sim.log") as sim,
    ):
        wait_until(lambda: probe.clock or sim.poll() is not None, what="the simulation's /clock")
        since = len(probe.clock)
        again = tool("launch", "--headless", *FAKE_TURTLEBOT)
        assert again.returncode == 1
        assert f"error: a simulation already runs on this graph: pid {sim.pid} on " in again.stderr
        assert "publishes /clock" in again.stderr
        model = EXAMPLES / "mbot_description/urdf/urdf/mbot_base.urdf"
        other = tool("sim", "--headless", str(model))
        assert other.returncode == 1
        assert f"pid {sim.pid} on" in other.stderr
        wait_until(lambda: len(probe.clock) > since + 20, what="the first /clock going on")
        assert sim.poll() is None
    assert probe.clock == sorted(probe.clock)


def test_a_plain_launch_and_a_script_first_graph(endpoint: str, tmp_path: Path) -> None:
    """A launch with no simulation in it (the mbot's display launch, headless) makes the graph
    and its time: a rospy script and ``topic echo`` joining agree with it. A graph that a
    script started alone (roscore's way) is on the wall clock: a launch of clients joining it,
    the script and the tools agree with that."""
    checker = tmp_path / "stamps.py"
    checker.write_text(STAMPS_SCRIPT)
    display = [
        *BELVEDERE,
        "launch",
        "--headless",
        "mbot_description",
        "display_mbot_base_urdf.launch",
    ]
    with probing(endpoint) as probe, running(display, tmp_path / "display.log") as first:
        wait_until(lambda: probe.clock or first.poll() is not None, what="the launch's /clock")
        stamps = tool("run", str(checker), "1.0")
        echo = tool("topic", "echo", "--offset", "-n", "3", "/joint_states")
    assert "use_sim_time True" in stamps.stdout, stamps.stdout + stamps.stderr
    assert echo.returncode == 0, echo.stderr
    assert all(abs(o) <= SAME_BASE for o in offsets(echo.stdout, 3)), echo.stdout
    checks = [(stamps.stdout, True)]
    # the script first: it provides the graph, on the wall clock; the same launch joins it
    script_log = tmp_path / "script.log"
    with running([*BELVEDERE, "run", str(checker), "8.0"], script_log) as script:
        wait_until(lambda: "use_sim_time False" in script_log.read_text(), what="the script")
        with running(display, tmp_path / "joined.log"):
            wait_until(lambda: script.poll() is not None, what="the script's end")
            echo = tool("topic", "echo", "--offset", "-n", "3", "/joint_states")
    assert echo.returncode == 0, echo.stderr
    assert all(abs(o) <= SAME_BASE for o in offsets(echo.stdout, 3)), echo.stdout
    checks.append((script_log.read_text(), False))
    for output, simulated in checks:
        seen = lags(output)
        assert set(seen) == {"/joint_states", "/tf"}, output
        for topic, (count, least, most) in seen.items():
            assert count > 0
            assert -SAME_BASE <= least <= most <= SAME_BASE, (simulated, topic, least, most)


def test_mapping_while_navigating_in_three_terminals(endpoint: str, tmp_path: Path) -> None:
    """The course's exploring_slam demo as the course runs it: the physics cloister with
    the laser mbot in one terminal, slam_gmapping under move_base in a second, the rospy
    goal script in a third, and map_saver in a fourth — all in the simulation's time."""
    sim_words = ["launch", "--headless", "mbot_gazebo", "mbot_laser_nav_gazebo.launch"]
    with (
        probing(endpoint) as probe,
        running([*BELVEDERE, *sim_words, "gui:=false"], tmp_path / "sim.log") as sim,
    ):
        wait_until(lambda: probe.odom or sim.poll() is not None, what="the simulation's /odom")
        assert sim.poll() is None, (tmp_path / "sim.log").read_text()
        slam = [*BELVEDERE, "launch", "--headless", "mbot_navigation", "exploring_slam_demo.launch"]
        with running(slam, tmp_path / "slam.log") as second:
            goals = subprocess.run(
                [*BELVEDERE, "run", "mbot_navigation", "exploring_slam.py"],
                capture_output=True,
                text=True,
                timeout=DEADLINE * 6,
                check=False,
            )
            out = goals.stdout + goals.stderr
            assert "Reached 2 of 2 goals" in out, out[-2000:]
            saved = tool("run", "map_server", "map_saver", "-f", str(tmp_path / "explored"))
            assert saved.returncode == 0, saved.stderr
            assert second.poll() is None
            assert sim.poll() is None
    slam_log = (tmp_path / "slam.log").read_text()
    assert "transform timeout" not in slam_log, slam_log[-2000:]
    grid = load_map(tmp_path / "explored.yaml")
    assert int((grid.data == OCCUPIED).sum()) > 100  # the cloister's walls, mapped
    assert probe.worst_lag() <= SAME_BASE
