"""The differential harness against Debian's ROS 1 robot_state_publisher (1.15).

A real roscore on a port of its own (and a ROS_HOME of its own), the real
robot_state_publisher fed ``joint_states`` by a rospy script run with ``/usr/bin/python3``, in
simulated time (the script drives ``/clock``); what it publishes on ``/tf`` and ``/tf_static``
is recorded and compared with what belvedere's :class:`RobotStatePublisher` publishes for the
same model, parameters and messages in belvedere's simulated time.

After each message the script sends a probe: a message about one extra continuous joint
(``belvedere_probe``, added to every model) whose transform marks the end of that message's
output, so a message that publishes nothing is seen to publish nothing.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import socket
import subprocess
import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from belvedere.description.urdf import RobotModel
from belvedere.graph import NS, Graph
from belvedere.msgs import build
from belvedere.tf import RobotStatePublisher
from tests.debian_ros import ROS_PYTHON, ROSCORE, missing_debian_ros

RSP_BINARY = Path("/usr/lib/robot_state_publisher/robot_state_publisher")
PROBE = "belvedere_probe"
PROBE_STAMP_NS = 10**15
"""Probes are stamped far ahead of every message (10⁶ s), a second apart, so the
publish_frequency throttle always lets them through."""
STATIC_TICK_NS = 1_000_000
"""The script moves ``/clock`` on by 1 ms until the static transforms come."""

Record = tuple[str, list[tuple[int, int, str, str, list[float], list[float]]]]
"""One message: topic, then (seq, stamp ns, frame, child, translation, quat_xyzw) each."""


def missing_oracle() -> str | None:
    """Why the ROS side cannot run here, or None."""
    return missing_debian_ros("rospy, tf2_msgs.msg, sensor_msgs.msg", RSP_BINARY)


@dataclass(frozen=True)
class JointStates:
    stamp_ns: int
    name: Sequence[str]
    position: Sequence[float]


@dataclass(frozen=True)
class Case:
    """One comparison: a model, node parameters (private, without ``~``) and messages."""

    name: str
    urdf: str
    messages: Sequence[JointStates]
    params: Mapping[str, Any] = field(default_factory=dict)
    clock_ns: int = 50 * NS
    """Simulated time while the messages are sent (after the static transforms)."""

    def probed_urdf(self) -> str:
        """The model with the probe joint on its root link."""
        root = RobotModel.from_string(self.urdf).root_link.name
        probe = (
            f'<link name="{PROBE}_link"/><joint name="{PROBE}" type="continuous">'
            f'<parent link="{root}"/><child link="{PROBE}_link"/></joint></robot>'
        )
        head, _, _ = self.urdf.rpartition("</robot>")
        return head + probe


ORACLE_SCRIPT = r"""
import json, subprocess, sys, time
import rospy
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState
from tf2_msgs.msg import TFMessage

RSP, PROBE, PROBE_STAMP_NS, TICK = sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5])


def stamp(ns):
    return rospy.Time(ns // 10**9, ns % 10**9)


def recorder(topic, out):
    def callback(msg):
        out.append([topic, [[
            t.header.seq, t.header.stamp.to_nsec(), t.header.frame_id, t.child_frame_id,
            [t.transform.translation.x, t.transform.translation.y, t.transform.translation.z],
            [t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
             t.transform.rotation.w],
        ] for t in msg.transforms]])
    return callback


def wait(condition, what, timeout=30.0):
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            raise SystemExit("oracle: timed out waiting for " + what)
        time.sleep(0.002)


case = json.load(open(sys.argv[1]))
node_name = case["node"]
rospy.init_node("rsp_oracle", disable_signals=True)
rospy.set_param("/use_sim_time", True)
rospy.set_param("/robot_description", case["urdf"])
for key, value in case["params"].items():
    rospy.set_param("/" + node_name + "/" + key, value)
out = []
clock = rospy.Publisher("/clock", Clock, queue_size=10)
states = rospy.Publisher("/joint_states", JointState, queue_size=10)
rospy.Subscriber("/tf", TFMessage, recorder("/tf", out), queue_size=1000)
rospy.Subscriber("/tf_static", TFMessage, recorder("/tf_static", out), queue_size=1000)
node = subprocess.Popen([RSP, "__name:=" + node_name], stdout=subprocess.DEVNULL,
                        stderr=subprocess.PIPE, text=True)
try:
    wait(lambda: states.get_num_connections() > 0 and clock.get_num_connections() > 0,
         "robot_state_publisher to subscribe")
    # the static transforms come on a one-shot timer, 1/publish_frequency after the start
    ns = 0
    while not any(t == "/tf_static" for t, _ in out):
        ns += TICK
        clock.publish(Clock(stamp(ns)))
        time.sleep(0.01)
        if ns > 2 * 10**9:
            raise SystemExit("oracle: nothing on /tf_static")
    clock.publish(Clock(stamp(case["clock_ns"])))
    time.sleep(0.3)  # the clock and the joint states come on connections of their own
    for k, m in enumerate(case["messages"]):
        before = len(out)
        msg = JointState()
        msg.header.stamp = stamp(m["stamp_ns"])
        msg.name, msg.position = m["name"], m["position"]
        states.publish(msg)
        # robot_state_publisher's queue holds one message: let it take this one before the
        # probe comes (one it leaves out publishes nothing, hence the bounded wait)
        end = time.monotonic() + 0.25
        while len(out) == before and time.monotonic() < end:
            time.sleep(0.002)
        probe = JointState()
        probe.header.stamp = stamp(PROBE_STAMP_NS + k * 10**9)
        probe.name, probe.position = [PROBE], [float(k)]
        states.publish(probe)
        wait(lambda: any(t == "/tf" and tfs and tfs[0][1] == PROBE_STAMP_NS + k * 10**9
                         for t, tfs in out[before:]), "the probe after message %d" % k)
finally:
    node.terminate()
    _, err = node.communicate(timeout=10)
json.dump({"out": out, "stderr": err}, sys.stdout)
"""


@dataclass
class Roscore:
    """A real roscore on a port of its own."""

    port: int
    home: Path
    process: subprocess.Popen[bytes]

    @property
    def env(self) -> dict[str, str]:
        return ros_env(self.port, self.home)


def ros_env(port: int, home: Path) -> dict[str, str]:
    """The environment of a ROS 1 process on the master at ``port``."""
    env = dict(os.environ)
    env["PATH"] = "/usr/bin:" + env.get("PATH", "")
    env["ROS_MASTER_URI"] = f"http://127.0.0.1:{port}"
    env["ROS_HOME"] = str(home)
    env["ROS_LOG_DIR"] = str(home / "log")
    env.pop("PYTHONPATH", None)
    return env


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


def start_roscore(home: Path) -> Iterator[Roscore]:
    """A roscore for a fixture (stopped when the generator resumes)."""
    home.mkdir(parents=True, exist_ok=True)
    port = free_port()
    process = subprocess.Popen(
        [str(ROSCORE), "-p", str(port)],
        env=ros_env(port, home),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    core = Roscore(port, home, process)
    deadline = time.monotonic() + 60
    while True:
        check = subprocess.run(
            [
                str(ROS_PYTHON),
                "-c",
                "import rosgraph,sys; sys.exit(not rosgraph.is_master_online())",
            ],
            env=core.env,
            capture_output=True,
            check=False,
        )
        if check.returncode == 0:
            break
        if time.monotonic() > deadline or core.process.poll() is not None:
            msg = f"roscore on port {port} did not come up"
            raise RuntimeError(msg)
        time.sleep(0.2)
    try:
        yield core
    finally:
        os.killpg(core.process.pid, 15)
        core.process.wait(timeout=30)
        shutil.rmtree(home / "log", ignore_errors=True)


def run_oracle(core: Roscore, case: Case, workdir: Path) -> tuple[list[Record], str]:
    """What Debian's robot_state_publisher publishes for ``case`` (records, its stderr)."""
    data = {
        "node": f"rsp_{case.name}",
        "urdf": case.probed_urdf(),
        "params": dict(case.params),
        "clock_ns": case.clock_ns,
        "messages": [
            {"stamp_ns": m.stamp_ns, "name": list(m.name), "position": list(m.position)}
            for m in case.messages
        ],
    }
    case_file = workdir / f"{case.name}.json"
    case_file.write_text(json.dumps(data))
    script = workdir / "rsp_oracle.py"
    script.write_text(ORACLE_SCRIPT)
    proc = subprocess.run(
        [
            str(ROS_PYTHON),
            str(script),
            str(case_file),
            str(RSP_BINARY),
            PROBE,
            str(PROBE_STAMP_NS),
            str(STATIC_TICK_NS),
        ],
        env=core.env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    if proc.returncode != 0:
        msg = f"oracle failed ({proc.returncode}): {proc.stderr}"
        raise RuntimeError(msg)
    result = json.loads(proc.stdout)
    records: list[Record] = [(topic, [tuple(t) for t in tfs]) for topic, tfs in result["out"]]
    return records, str(result["stderr"])


def run_belvedere(case: Case) -> list[Record]:
    """What belvedere's RobotStatePublisher publishes for ``case``, in simulated time."""
    graph = Graph(clock_hz=None)
    graph.params.set("/robot_description", case.probed_urdf())
    node = graph.create_node(f"rsp_{case.name}", params=dict(case.params))
    out: list[Record] = []

    def recorder(topic: str) -> Any:
        def callback(msg: Any) -> None:
            out.append(
                (
                    topic,
                    [
                        (
                            t.header.seq,
                            t.header.stamp.sec * NS + t.header.stamp.nanosec,
                            t.header.frame_id,
                            t.child_frame_id,
                            [
                                t.transform.translation.x,
                                t.transform.translation.y,
                                t.transform.translation.z,
                            ],
                            [
                                t.transform.rotation.x,
                                t.transform.rotation.y,
                                t.transform.rotation.z,
                                t.transform.rotation.w,
                            ],
                        )
                        for t in msg.transforms
                    ],
                )
            )

        return callback

    listener = graph.create_node("rsp_oracle")
    listener.subscribe("/tf", "tf2_msgs/TFMessage", recorder("/tf"), queue_size=1000)
    listener.subscribe("/tf_static", "tf2_msgs/TFMessage", recorder("/tf_static"), queue_size=1000)
    states = listener.publisher("/joint_states", "sensor_msgs/JointState", seq_rule="rospy")
    RobotStatePublisher(node)
    graph.run(until=lambda: any(topic == "/tf_static" for topic, _ in out))
    graph.run(duration=(case.clock_ns - graph.now_ns()) / NS)
    for k, m in enumerate(case.messages):
        states.publish(build.joint_state(m.stamp_ns, list(m.name), list(m.position), [], []))
        graph.spin_once()
        probe_ns = PROBE_STAMP_NS + k * NS
        states.publish(build.joint_state(probe_ns, [PROBE], [float(k)], [], []))
        graph.spin_once()
    return out


@dataclass
class Comparison:
    """How two runs differ: structural mismatches and the largest numeric differences."""

    transforms: int = 0
    messages: int = 0
    mismatches: list[str] = field(default_factory=list)
    max_translation: float = 0.0
    max_rotation: float = 0.0
    """Largest difference of a quaternion component (after fixing the sign of q ≡ -q)."""
    bit_equal: int = 0


STATIC_LAG_TICKS = 5
"""ROS's static transforms come on a wall-clock timer while the oracle script moves /clock on
a tick every 10 ms: on a busy machine the timer fires a tick or more late, so the stamp it
reads is that much later than the period belvedere stamps."""


def _static_stamps_agree(
    expected: list[tuple[int, int, str, str]], actual: list[tuple[int, int, str, str]]
) -> bool:
    return len(expected) == len(actual) and all(
        (e[0], e[2], e[3]) == (a[0], a[2], a[3])
        and 0 <= e[1] - a[1] <= STATIC_LAG_TICKS * STATIC_TICK_NS
        for e, a in zip(expected, actual, strict=True)
    )


def compare(expected: list[Record], actual: list[Record]) -> Comparison:
    """Compare the oracle's records with belvedere's, message by message."""
    result = Comparison()
    if len(expected) != len(actual):
        result.mismatches.append(
            f"{len(expected)} messages from ROS, {len(actual)} from belvedere: "
            f"{[(t, len(x)) for t, x in expected]} vs {[(t, len(x)) for t, x in actual]}"
        )
    for i, ((topic_e, tfs_e), (topic_a, tfs_a)) in enumerate(zip(expected, actual, strict=False)):
        result.messages += 1
        keys_e = [t[:4] for t in tfs_e]
        keys_a = [t[:4] for t in tfs_a]
        if topic_e == topic_a == "/tf_static" and _static_stamps_agree(keys_e, keys_a):
            keys_e = keys_a
        if topic_e != topic_a or keys_e != keys_a:
            result.mismatches.append(
                f"message {i}: ROS {topic_e} {keys_e}, belvedere {topic_a} {keys_a}"
            )
            continue
        for te, ta in zip(tfs_e, tfs_a, strict=True):
            result.transforms += 1
            qe, qa = te[5], ta[5]
            if sum(x * y for x, y in zip(qe, qa, strict=True)) < 0:
                qa = [-x for x in qa]
            dt = max(abs(x - y) for x, y in zip(te[4], ta[4], strict=True))
            dq = max(abs(x - y) for x, y in zip(qe, qa, strict=True))
            result.max_translation = max(result.max_translation, dt)
            result.max_rotation = max(result.max_rotation, dq)
            if list(te[4]) == list(ta[4]) and list(te[5]) == list(ta[5]):
                result.bit_equal += 1
            if not (math.isfinite(dt) and math.isfinite(dq)):
                result.mismatches.append(f"message {i}: {te[3]}: not finite")
    return result
