"""Messages between ROS 1 programs and belvedere over TCPROS, against ROS 1 with itself,
same run.

For 1 KB and 1 MB ``std_msgs/String`` messages, each sent as fast as the sender can for a few
seconds (its send time written at the start of the text, so the receiver measures latency):

- reference: a ROS 1 publisher to a ROS 1 subscriber through Debian's own roscore;
- ROS 1 → belvedere: the same publisher to a graph subscriber through
  ``belvedere roscore``'s master and bridge;
- belvedere → ROS 1: a graph publisher to the same subscriber.

Messages per second received and mean latency, and the ratios to the reference; and the CPU
each message costs belvedere's side (the receiving process's CPU over the messages it got,
the sending process's CPU a second over the messages received a second) against what it
costs the same side of the reference: on a machine others share, the messages a second
follow whoever else runs, the CPU a message much less. The ROS 1
side is Debian's rospy (``/usr/bin/python3``), Debian's roscpp (two nodes compiled here with
g++ against ``libroscpp-dev``, kept in ~/.cache/belvedere-bench), or both in turn.

    python benchmarks/ros1_wire.py [--seconds 5] [--client rospy|roscpp|both]
"""

from __future__ import annotations

import argparse
import hashlib
import os
import resource
import socket
import subprocess
import tempfile
import threading
import time
import xmlrpc.client
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from belvedere.graph import Graph, ZenohTransport
from belvedere.msgs import types
from belvedere.ros1wire import start_master

ROS_PYTHON = "/usr/bin/python3"
SIZES = {"1 KB": 1024, "1 MB": 1024 * 1024}

PUBLISHER = """
import sys, time, rospy
from std_msgs.msg import String
size, seconds = int(sys.argv[1]), float(sys.argv[2])
rospy.init_node("flood_pub", anonymous=True)
pub = rospy.Publisher("/flood", String, queue_size=1000)
while pub.get_num_connections() == 0 and not rospy.is_shutdown():
    time.sleep(0.01)
time.sleep(0.5)
pad = "x" * size
end = time.time() + seconds
cpu, wall = time.process_time(), time.time()
while time.time() < end and not rospy.is_shutdown():
    pub.publish(String(data="%.6f|" % time.time() + pad))
print((time.process_time() - cpu) / (time.time() - wall), flush=True)
time.sleep(0.5)
"""

SUBSCRIBER = """
import sys, time, rospy
from std_msgs.msg import String
seconds = float(sys.argv[1])
got = []
def take(m):
    got.append((time.time(), float(m.data[:m.data.index("|")])))
rospy.init_node("flood_sub", anonymous=True)
rospy.Subscriber("/flood", String, take, queue_size=1000, buff_size=1 << 24)
print("READY", flush=True)
while not got and not rospy.is_shutdown():
    time.sleep(0.005)
first, cpu = len(got), time.process_time()
time.sleep(seconds)
n = len(got)
cpu = (time.process_time() - cpu) / max(n - first, 1)
span = got[-1][0] - got[0][0]
print(n / span if span > 0 else 0.0, sum(a - b for a, b in got) / n, cpu)
"""

CPP_PUBLISHER = r"""
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <cstdio>
#include <ctime>
#include <string>
static double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}
int main(int argc, char** argv) {
  ros::init(argc, argv, "flood_pub", ros::init_options::AnonymousName);
  size_t size = std::stoul(argv[1]);
  double seconds = std::stod(argv[2]);
  ros::NodeHandle n;
  ros::Publisher pub = n.advertise<std_msgs::String>("/flood", 1000);
  while (pub.getNumSubscribers() == 0 && ros::ok()) ros::WallDuration(0.01).sleep();
  ros::WallDuration(0.5).sleep();
  std::string pad(size, 'x');
  double end = ros::WallTime::now().toSec() + seconds;
  std_msgs::String msg;
  char stamp[32];
  double cpu = cpu_seconds(), wall = ros::WallTime::now().toSec();
  while (ros::ok() && ros::WallTime::now().toSec() < end) {
    std::snprintf(stamp, sizeof stamp, "%.6f|", ros::WallTime::now().toSec());
    msg.data = stamp + pad;
    pub.publish(msg);
  }
  std::printf("%.6f\n", (cpu_seconds() - cpu) / (ros::WallTime::now().toSec() - wall));
  std::fflush(stdout);
  ros::WallDuration(0.5).sleep();
  return 0;
}
"""

CPP_SUBSCRIBER = r"""
#include <ros/ros.h>
#include <ros/callback_queue.h>
#include <std_msgs/String.h>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>
static std::vector<std::pair<double, double>> got;
static double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}
static void take(const std_msgs::String::ConstPtr& m) {
  got.emplace_back(ros::WallTime::now().toSec(), std::atof(m->data.c_str()));
}
int main(int argc, char** argv) {
  ros::init(argc, argv, "flood_sub", ros::init_options::AnonymousName);
  double seconds = std::stod(argv[1]);
  ros::NodeHandle n;
  ros::Subscriber sub = n.subscribe("/flood", 1000, take);
  std::printf("READY\n");
  std::fflush(stdout);
  ros::CallbackQueue* queue = ros::getGlobalCallbackQueue();
  while (got.empty() && ros::ok()) queue->callAvailable(ros::WallDuration(0.01));
  size_t first = got.size();
  double cpu = cpu_seconds();
  double end = ros::WallTime::now().toSec() + seconds;
  while (ros::ok() && ros::WallTime::now().toSec() < end)
    queue->callAvailable(ros::WallDuration(0.01));
  size_t count = got.size();
  cpu = (cpu_seconds() - cpu) / (count > first ? count - first : 1);
  double span = got.back().first - got.front().first, lag = 0;
  for (auto& g : got) lag += g.first - g.second;
  std::printf("%f %f %.9f\n", span > 0 ? count / span : 0.0, lag / count, cpu);
  return 0;
}
"""

ROSCPP_LIBS = ["-lroscpp", "-lrosconsole", "-lroscpp_serialization", "-lrostime", "-lcpp_common"]


def _compiled(source: str, name: str) -> str:
    """``source`` built with g++ against Debian's roscpp, once per text."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    folder = Path.home() / ".cache" / "belvedere-bench" / f"ros1_wire-{digest}"
    binary = folder / name
    if not binary.exists():
        folder.mkdir(parents=True, exist_ok=True)
        (folder / f"{name}.cpp").write_text(source)
        subprocess.run(
            ["g++", "-O2", "-o", str(binary), str(folder / f"{name}.cpp"), *ROSCPP_LIBS],
            check=True,
        )
    return str(binary)


def _commands(client: str, folder: Path) -> tuple[list[str], list[str]]:
    """The publisher's and the subscriber's command (their arguments follow)."""
    if client == "roscpp":
        return [_compiled(CPP_PUBLISHER, "pub")], [_compiled(CPP_SUBSCRIBER, "sub")]
    return (
        [ROS_PYTHON, _script(PUBLISHER, folder, "pub.py")],
        [ROS_PYTHON, _script(SUBSCRIBER, folder, "sub.py")],
    )


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _env(uri: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "ROS_"))}
    env.update(PATH="/usr/bin:" + env.get("PATH", ""), ROS_MASTER_URI=uri)
    env["ROS_HOSTNAME"] = "127.0.0.1"
    return env


def _script(text: str, directory: Path, name: str) -> str:
    path = directory / name
    path.write_text(text)
    return str(path)


def _subscriber(uri: str, seconds: float, command: list[str]) -> subprocess.Popen[str]:
    proc = subprocess.Popen(
        [*command, str(seconds)],
        env=_env(uri),
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    assert proc.stdout.readline().strip() == "READY"
    return proc


@dataclass(frozen=True)
class Run:
    rate: float
    """messages received per second"""
    latency: float
    """mean seconds from send to receipt"""
    sender_cpu: float
    """the sending process's CPU seconds per message received"""
    receiver_cpu: float
    """the receiving process's CPU seconds per message received"""


def _received(proc: subprocess.Popen[str]) -> tuple[float, float, float]:
    """A ROS 1 subscriber's messages per second, mean latency and CPU seconds a message."""
    out, _ = proc.communicate(timeout=120)
    rate, latency, cpu = out.split()[-3:]
    return float(rate), float(latency), float(cpu)


def _sender_cores(proc: subprocess.Popen[str]) -> float:
    """A ROS 1 publisher's CPU seconds per second while it sent."""
    out, _ = proc.communicate(timeout=120)
    return float(out.split()[-1])


def _publisher(uri: str, size: int, seconds: float, command: list[str]) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [*command, str(size), str(seconds + 2)],
        env=_env(uri),
        stdout=subprocess.PIPE,
        text=True,
    )


def _cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def reference(size: int, seconds: float, ends: tuple[list[str], list[str]]) -> Run:
    port = _free_port()
    uri = f"http://127.0.0.1:{port}/"
    core = subprocess.Popen(
        ["/usr/bin/roscore", "-p", str(port)],
        env=_env(uri),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        while True:
            try:
                xmlrpc.client.ServerProxy(uri).getUri("/bench")
                break
            except OSError:
                time.sleep(0.1)
        sub = _subscriber(uri, seconds, ends[1])
        pub = _publisher(uri, size, seconds, ends[0])
        rate, latency, receiver = _received(sub)
        return Run(rate, latency, _sender_cores(pub) / rate, receiver)
    finally:
        os.killpg(core.pid, 2)
        core.wait(timeout=30)


def _graph() -> tuple[Graph, Any]:
    endpoint = f"tcp/127.0.0.1:{_free_port()}"
    graph = Graph(sim_time=False, transport=ZenohTransport(endpoint=endpoint), clock_hz=None)
    graph.start(rtf=None)
    return graph, start_master(graph, port=0)


def ros1_to_graph(size: int, seconds: float, ends: tuple[list[str], list[str]]) -> Run:
    graph, handle = _graph()
    got: list[tuple[float, float]] = []

    def take(msg: Any) -> None:
        got.append((time.time(), float(msg.data[: msg.data.index("|")])))

    graph.create_node("flood_sub").subscribe("/flood", "std_msgs/String", take, queue_size=1000)
    try:
        pub = _publisher(handle.uri, size, seconds, ends[0])
        while not got:
            time.sleep(0.005)
        first, cpu = len(got), _cpu_seconds()
        time.sleep(seconds)
        n, cpu = len(got), _cpu_seconds() - cpu
        span = got[-1][0] - got[0][0]
        rate = n / span
        return Run(
            rate,
            sum(a - b for a, b in got[:n]) / n,
            _sender_cores(pub) / rate,
            cpu / (n - first),
        )
    finally:
        handle.close()
        graph.shutdown()


def graph_to_ros1(size: int, seconds: float, ends: tuple[list[str], list[str]]) -> Run:
    graph, handle = _graph()
    pub = graph.create_node("flood_pub").publisher("/flood", "std_msgs/String", queue_size=1000)
    pad = "x" * size
    burst = max(1, min(50, (1 << 20) // size))
    string = types().cls("std_msgs/msg/String")
    stop = threading.Event()

    def flood() -> None:
        while not stop.is_set():
            done = threading.Event()

            def send(done: threading.Event = done) -> None:
                # a node's burst: up to 50 messages (1 MB) per turn of the executor, fewer
                # than the bridge's queue holds for a ROS 1 subscriber (100: as roscpp's
                # queue, it drops past its size); each made as rospy's sender makes its
                # String(data=...)
                for _ in range(burst):
                    pub.publish(string(data=f"{time.time():.6f}|{pad}"))
                done.set()

            graph.executor.post(send)
            done.wait()

    try:
        sub = _subscriber(handle.uri, seconds, ends[1])
        thread = threading.Thread(target=flood, daemon=True)
        cpu, wall = _cpu_seconds(), time.monotonic()
        thread.start()
        rate, latency, receiver = _received(sub)
        cores = (_cpu_seconds() - cpu) / (time.monotonic() - wall)
        stop.set()
        thread.join()
        return Run(rate, latency, cores / rate, receiver)
    finally:
        handle.close()
        graph.shutdown()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--client", choices=("rospy", "roscpp", "both"), default="both")
    args = parser.parse_args()
    clients = ("rospy", "roscpp") if args.client == "both" else (args.client,)
    with tempfile.TemporaryDirectory() as tmp:
        for client in clients:
            ends = _commands(client, Path(tmp))
            for label, size in SIZES.items():
                ref = reference(size, args.seconds, ends)
                into = ros1_to_graph(size, args.seconds, ends)
                out = graph_to_ros1(size, args.seconds, ends)
                print(
                    f"{label}: {client} → {client} (Debian's roscore): {ref.rate:8.0f} msg/s, "
                    f"latency {ref.latency * 1e3:6.2f} ms; CPU a message: sender "
                    f"{ref.sender_cpu * 1e6:.2f} µs, receiver {ref.receiver_cpu * 1e6:.2f} µs"
                )
                # belvedere's side against the same side of the reference: the receiver's
                # CPU for ROS 1 → belvedere, the sender's for belvedere → ROS 1
                for what, got, ours, theirs in (
                    (f"{client} → belvedere", into, into.receiver_cpu, ref.receiver_cpu),
                    (f"belvedere → {client}", out, out.sender_cpu, ref.sender_cpu),
                ):
                    print(
                        f"{label}: {what:30s}: {got.rate:8.0f} msg/s, latency "
                        f"{got.latency * 1e3:6.2f} ms  ({got.rate / ref.rate:.2f}x the "
                        f"reference's msg/s); belvedere's CPU a message {ours * 1e6:.2f} µs "
                        f"({ours / theirs:.2f}x {client}'s)"
                    )


if __name__ == "__main__":
    main()
