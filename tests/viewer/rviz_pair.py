"""A screenshot pair: Debian's rviz 1.14 and belvedere's viewer showing the same running
launch with the same ``.rviz`` config (issue 17's side-by-side comparison).

    python -m tests.viewer.rviz_pair OUTDIR [--launch FILE] [--seconds 12]

rviz speaks ROS 1's transport, so a bridge carries the launch's topics to a real roscore:
a rospy script run by ``belvedere run`` (belvedere's rospy, on belvedere's graph) writes each
message's ROS 1 bytes to a pipe, and Debian's rospy on the other end publishes them unchanged
(same type, md5 and definition) with the launch's ``robot_description`` and ``/use_sim_time``.
rviz runs under Xvfb and is grabbed from the X display; the viewer is the page ``belvedere run
rviz rviz -d CONFIG`` serves, in Debian's Chromium at the same size.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from PIL import Image, ImageGrab

from belvedere.graph import graph_running
from belvedere.viewer._chromium import launch_chromium
from tests.conftest import EXAMPLES
from tests.debian_ros import ROS_PYTHON
from tests.tf.ros1 import start_roscore

SIZE = (1000, 700)
LAUNCH = EXAMPLES / "mbot_gazebo/launch/view_mbot_with_laser_gazebo.launch"
TOPICS = (  # (topic, message module, class, latched)
    ("/clock", "rosgraph_msgs.msg", "Clock", False),
    ("/tf", "tf2_msgs.msg", "TFMessage", False),
    ("/tf_static", "tf2_msgs.msg", "TFMessage", True),
    ("/scan", "sensor_msgs.msg", "LaserScan", False),
    ("/odom", "nav_msgs.msg", "Odometry", False),
)
CONFIG = f"""Panels: []
Visualization Manager:
  Class: ""
  Displays:
    - {{Class: rviz/Grid, Name: Grid, Enabled: true, Plane Cell Count: 10, Cell Size: 1}}
    - {{Class: rviz/RobotModel, Name: RobotModel, Enabled: true,
        Robot Description: robot_description}}
    - {{Class: rviz/LaserScan, Name: LaserScan, Enabled: true, Topic: /scan, Size (m): 0.05,
        Style: Flat Squares, Color Transformer: FlatColor, Color: "255; 0; 0", Decay Time: 0}}
    - {{Class: rviz/Odometry, Name: Odometry, Enabled: true, Topic: /odom, Keep: 20}}
  Global Options: {{Fixed Frame: odom, Background Color: "48; 48; 48", Frame Rate: 30}}
  Views:
    Current: {{Class: rviz/Orbit, Distance: 8, Pitch: 0.7, Yaw: 3.9,
      Focal Point: {{X: 0, Y: 0, Z: 0}}, Target Frame: <Fixed Frame>}}
Window Geometry: {{Width: {SIZE[0]}, Height: {SIZE[1]}, X: 0, Y: 0, Hide Left Dock: true,
  Hide Right Dock: true, Displays: {{collapsed: true}}, Views: {{collapsed: true}}}}
"""

# belvedere's side: a rospy script on belvedere's graph, writing each message's ROS 1 bytes.
OUT = """
import io, struct, sys, threading, importlib
import rospy
TOPICS = %r
pipe, lock = sys.stdout.buffer, threading.Lock()
def put(kind, *parts):
    data = b"".join(struct.pack("<I", len(p)) + p for p in parts)
    with lock:
        pipe.write(kind + struct.pack("<I", len(data)) + data)
        pipe.flush()
rospy.init_node("ros1_bridge", anonymous=True)
put(b"P", b"/robot_description", rospy.get_param("/robot_description").encode())
put(b"P", b"/use_sim_time", b"1")
for topic, module, name, latched in TOPICS:
    cls = getattr(importlib.import_module(module), name)
    put(b"D", topic.encode(), cls._type.encode(), cls._md5sum.encode(),
        cls._full_text.encode(), b"1" if latched else b"0")
    def forward(msg, topic=topic):
        buff = io.BytesIO()
        msg.serialize(buff)
        put(b"M", topic.encode(), buff.getvalue())
    rospy.Subscriber(topic, cls, forward, queue_size=100)
rospy.spin()
"""

# ROS 1's side: Debian's rospy publishing the bytes as they came.
IN = """
import struct, sys
import genpy, rospy
from tf2_msgs.msg import TFMessage
class Raw(genpy.Message):
    __slots__ = ["raw"]
    _slot_types = ["uint8[]"]
    _has_header = False
    def __init__(self, raw=b""):
        self.raw = raw
    def serialize(self, buff):
        buff.write(self.raw)
    def deserialize(self, data):
        self.raw = data
        return self
rospy.init_node("belvedere_bridge")
pipe, pubs, static = sys.stdin.buffer, {}, {}
while not rospy.is_shutdown():
    head = pipe.read(5)
    if len(head) < 5:
        break
    data = pipe.read(struct.unpack("<I", head[1:])[0])
    parts, i = [], 0
    while i < len(data):
        n = struct.unpack("<I", data[i:i + 4])[0]
        parts.append(data[i + 4:i + 4 + n])
        i += 4 + n
    kind = head[:1]
    if kind == b"P":
        value = parts[1].decode()
        rospy.set_param(parts[0].decode(), True if value == "1" else value)
    elif kind == b"D":
        topic, kind_name, md5, text, latched = (p.decode() for p in parts)
        cls = type("Raw", (Raw,), {"__slots__": [], "_type": kind_name, "_md5sum": md5,
                                   "_full_text": text})
        pubs[topic] = (rospy.Publisher(topic, cls, queue_size=100, latch=latched == "1"), cls)
    else:
        topic, raw = parts[0].decode(), parts[1]
        pub, cls = pubs[topic]
        if topic == "/tf_static":  # one latched message holding every static transform
            for t in TFMessage().deserialize(raw).transforms:
                static[t.child_frame_id] = t
            out = __import__("io").BytesIO()
            TFMessage(transforms=list(static.values())).serialize(out)
            raw = out.getvalue()
        pub.publish(cls(raw))
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
    return port


@contextlib.contextmanager
def _process(command: list[str], **kw: object) -> Iterator[subprocess.Popen[bytes]]:
    process = subprocess.Popen(command, start_new_session=True, **kw)  # type: ignore[call-overload]
    try:
        yield process
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGTERM)
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait(timeout=15)


def _rviz_shot(config: Path, env: dict[str, str], seconds: float, out: Path) -> None:
    display = f":{90 + os.getpid() % 100}"
    screen = f"{SIZE[0]}x{SIZE[1]}x24"
    with _process(["Xvfb", display, "-screen", "0", screen], stderr=subprocess.DEVNULL):
        time.sleep(2)
        rviz_env = {**env, "DISPLAY": display, "HOME": str(out.parent / "home")}
        log = (out.parent / "rviz.log").open("wb")
        with _process(["/usr/bin/rviz", "-d", str(config)], env=rviz_env, stdout=log, stderr=log):
            time.sleep(seconds)
            ImageGrab.grab(xdisplay=display).save(out)


def _viewer_shot(config: Path, seconds: float, out: Path) -> None:
    from playwright.sync_api import sync_playwright

    port = free_port()
    command = [sys.executable, "-m", "belvedere", "run", "--port", str(port)]
    with _process([*command, "rviz", "rviz", "-d", str(config)], stderr=subprocess.PIPE) as run:
        assert run.stderr is not None
        url = ""
        while not url:
            line = run.stderr.readline().decode()
            if not line:
                msg = "belvedere run rviz ended"
                raise SystemExit(msg)
            if line.startswith("viewer: "):
                url = line.removeprefix("viewer: ").strip()
        with sync_playwright() as p:
            browser = launch_chromium(p, shutil.which("chromium"))
            page = browser.new_page(viewport={"width": SIZE[0], "height": SIZE[1]})
            page.goto(url)
            page.wait_for_selector("canvas")
            time.sleep(seconds)
            page.screenshot(path=str(out))
            browser.close()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("outdir", type=Path)
    parser.add_argument("--launch", type=Path, default=LAUNCH)
    parser.add_argument("--seconds", type=float, default=12.0)
    args = parser.parse_args()
    out: Path = args.outdir.resolve()
    (out / "home").mkdir(parents=True, exist_ok=True)
    config = out / "pair.rviz"
    config.write_text(CONFIG)
    (out / "bridge_out.py").write_text(OUT % (TOPICS,))
    (out / "bridge_in.py").write_text(IN)
    launch = [sys.executable, "-m", "belvedere", "launch", "--headless", str(args.launch)]
    with _process(launch, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL):
        deadline = time.monotonic() + 60
        while not graph_running():
            if time.monotonic() > deadline:
                msg = "the launch's graph did not come up"
                raise SystemExit(msg)
            time.sleep(0.2)
        core = start_roscore(out / "ros")
        roscore = next(core)
        try:
            bridge = [sys.executable, "-m", "belvedere", "run", str(out / "bridge_out.py")]
            with (
                _process(bridge, stdout=subprocess.PIPE) as source,
                _process([str(ROS_PYTHON), str(out / "bridge_in.py")], stdin=source.stdout,
                         env=roscore.env),
            ):  # fmt: skip
                time.sleep(3)
                _rviz_shot(config, roscore.env, args.seconds, out / "rviz.png")
                _viewer_shot(config, args.seconds, out / "belvedere.png")
        finally:
            with contextlib.suppress(StopIteration):
                next(core)
    pair = Image.new("RGB", (SIZE[0] * 2, SIZE[1]))
    pair.paste(Image.open(out / "rviz.png").convert("RGB").resize(SIZE), (0, 0))
    pair.paste(Image.open(out / "belvedere.png").convert("RGB").resize(SIZE), (SIZE[0], 0))
    pair.save(out / "pair.png")
    sys.stdout.write(f"{out / 'pair.png'}: Debian's rviz (left), belvedere (right)\n")


if __name__ == "__main__":
    main()
