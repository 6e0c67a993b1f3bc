"""How soon a script's new subscriptions get their first messages from another process, with
Debian's ROS 1 (roscore, rospy) as the reference in the same run.

Another process publishes a latched ``/tf_static`` and ``/tf`` at 50 Hz; a script subscribes
to both (as ``tf2_ros.TransformListener`` does) and notes when each first message reaches its
callback, counted from the ``Subscriber`` call. belvedere: the publisher is a belvedere graph,
the script runs with ``belvedere run``. ROS: a rospy publisher, ``python3`` with Debian's
rospy, against a roscore this starts. ``--load N`` runs N busy processes meanwhile (a loaded
machine, where the difference shows).

    python benchmarks/first_messages.py [--runs 9] [--load 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from debian_ros import DEBIAN_PYTHON, ROSCORE, free_port

PROBE = """\
import os, sys, threading, time
import rospy
from tf2_msgs.msg import TFMessage
rospy.init_node("probe", anonymous=True)
first = {}
done = threading.Event()
def note(name):
    def callback(msg):
        first.setdefault(name, time.monotonic())
        if len(first) == 2:
            done.set()
    return callback
start = time.monotonic()
rospy.Subscriber("/tf_static", TFMessage, note("static"))
rospy.Subscriber("/tf", TFMessage, note("tf"))
done.wait(10)
print(*((first.get(k, float("nan")) - start) * 1000 for k in ("static", "tf")), flush=True)
os._exit(0)
"""

BELVEDERE_HOST = """\
import sys
from belvedere.graph import Graph, ZenohTransport
from belvedere.tf import static_transform_publisher
g = Graph(sim_time=False, transport=ZenohTransport(endpoint=sys.argv[1]))
n = g.create_node("host")
static_transform_publisher(n, ["0.1", "0", "0.2", "0", "0", "0", "base_link", "camera"])
tf = n.publisher("/tf", "tf2_msgs/TFMessage")
def tick():
    t = g.now_ns()
    stamp = {"sec": t // 10**9, "nanosec": t % 10**9}
    tf.publish_data({"transforms": [{"header": {"stamp": stamp, "frame_id": "odom"},
        "child_frame_id": "base_link", "transform": {"rotation": {"w": 1.0}}}]})
n.timer(0.02, tick)
g.start(rtf=None)
print("READY", flush=True)
sys.stdin.read()
g.shutdown()
"""

ROS_HOST = """\
import sys
import rospy
from geometry_msgs.msg import TransformStamped
from tf2_msgs.msg import TFMessage
rospy.init_node("host")
static = rospy.Publisher("/tf_static", TFMessage, latch=True, queue_size=1)
t = TransformStamped()
t.header.frame_id, t.child_frame_id, t.transform.rotation.w = "base_link", "camera", 1.0
static.publish(TFMessage([t]))
tf = rospy.Publisher("/tf", TFMessage, queue_size=10)
print("READY", flush=True)
rate = rospy.Rate(50)
while not rospy.is_shutdown():
    m = TransformStamped()
    m.header.stamp, m.header.frame_id, m.child_frame_id = rospy.Time.now(), "odom", "base_link"
    m.transform.rotation.w = 1.0
    tf.publish(TFMessage([m]))
    rate.sleep()
"""

BURN = "while True:\n    pass\n"


def probe(argv: list[str], env: dict[str, str], cwd: Path, runs: int) -> list[tuple[float, ...]]:
    found = []
    for _ in range(runs):
        out = subprocess.run(
            argv, env=env, cwd=cwd, capture_output=True, text=True, timeout=60, check=True
        ).stdout
        found.append(tuple(float(w) for w in out.split()))
    return found


def host(argv: list[str], env: dict[str, str]) -> subprocess.Popen[str]:
    proc = subprocess.Popen(argv, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    if proc.stdout.readline().strip() != "READY":
        msg = f"{argv[0]}: the publishing process did not start"
        raise SystemExit(msg)
    time.sleep(0.5)
    return proc


def stop(proc: subprocess.Popen[Any]) -> None:
    proc.terminate()
    proc.wait(30)


def ours(folder: Path, runs: int) -> list[tuple[float, ...]]:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    env = {**os.environ, "BELVEDERE_ENDPOINT": endpoint}
    publisher = host([sys.executable, "-c", BELVEDERE_HOST, endpoint], env)
    try:
        return probe([sys.executable, "-m", "belvedere", "run", "probe.py"], env, folder, runs)
    finally:
        stop(publisher)


def reference(folder: Path, runs: int) -> list[tuple[float, ...]] | None:
    if not (Path(ROSCORE).exists() and Path(DEBIAN_PYTHON).exists()):
        return None
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["ROS_MASTER_URI"] = f"http://127.0.0.1:{port}"
    env["ROS_HOME"] = str(folder / "ros_home")
    core = subprocess.Popen(
        [ROSCORE, "-p", str(port)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    try:
        time.sleep(3.0)  # the master, then rosout
        publisher = host([DEBIAN_PYTHON, "-c", ROS_HOST], env)
        try:
            return probe([DEBIAN_PYTHON, "probe.py"], env, folder, runs)
        finally:
            stop(publisher)
    finally:
        stop(core)


def show(name: str, results: list[tuple[float, ...]]) -> None:
    static = statistics.median(r[0] for r in results)
    periodic = statistics.median(r[1] for r in results)
    worst = max(r[0] for r in results)
    print(
        f"{name:10} first /tf_static {static:6.1f} ms (worst {worst:6.1f}), "
        f"first /tf {periodic:6.1f} ms (median of {len(results)})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=9)
    parser.add_argument("--load", type=int, default=0, metavar="N", help="N busy processes")
    args = parser.parse_args()
    burners = [subprocess.Popen([sys.executable, "-c", BURN]) for _ in range(args.load)]
    try:
        with tempfile.TemporaryDirectory() as tmp:
            folder = Path(tmp)
            (folder / "probe.py").write_text(PROBE)
            show("belvedere", ours(folder, args.runs))
            ros = reference(folder, args.runs)
            if ros is None:
                print("Debian's ROS 1 is not installed: no reference (scripts/install.sh --dev)")
            else:
                show("ROS 1", ros)
    finally:
        for burner in burners:
            burner.kill()
            burner.wait()


if __name__ == "__main__":
    main()
