"""Debian's rviz 1.14 as the oracle of ``.rviz`` files: it opens a config under Xvfb on a
roscore of its own, and saves what it made of it through its ``save_config`` service.

rviz advertises ``~save_config`` (``rviz/SendFilePath``) only after it has loaded the config
given with ``-d``, so the service appearing means every display was created (a display class it
cannot load is logged as an ERROR before that). Debian ships no Python module for rviz's
service types, so the script below speaks ``rviz/SendFilePath`` itself: a string request, a
bool reply, and ``*`` as its checksum (roscpp accepts that from a client).
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path

from tests.debian_ros import ROS_PYTHON, missing_debian_ros
from tests.tf.ros1 import Roscore, ros_env

RVIZ = Path("/usr/bin/rviz")
XVFB_RUN = Path("/usr/bin/xvfb-run")
WAIT_S = 20.0
"""How long rviz may take to come up and save (it needs about 2 s here)."""

_SAVE = r"""
import struct, sys, time

import genpy
import rosgraph
import rospy


class Request(genpy.Message):
    _md5sum = "*"
    _type = "rviz/SendFilePathRequest"
    _has_header = False
    _full_text = "std_msgs/String path"
    __slots__ = ["path"]
    _slot_types = ["std_msgs/String"]

    def __init__(self, path=""):
        self.path = path

    def serialize(self, buff):
        data = self.path.encode()
        buff.write(struct.pack("<I", len(data)) + data)


class Response(genpy.Message):
    _md5sum = "*"
    _type = "rviz/SendFilePathResponse"
    _has_header = False
    _full_text = "bool success"
    __slots__ = ["success"]
    _slot_types = ["bool"]

    def __init__(self):
        self.success = False

    def deserialize(self, data):
        self.success = bool(data[0])
        return self


class SendFilePath:
    _type = "rviz/SendFilePath"
    _md5sum = "*"
    _request_class = Request
    _response_class = Response


node, target, wait_s = sys.argv[1], sys.argv[2], float(sys.argv[3])
service = node + "/save_config"
master = rosgraph.Master("/belvedere_rviz_probe")
deadline = time.monotonic() + wait_s
while time.monotonic() < deadline:
    if any(name == service for name, _ in master.getSystemState()[2]):
        if not target:
            sys.exit(0)
        reply = rospy.ServiceProxy(service, SendFilePath)(Request(target))
        sys.exit(0 if reply.success else 3)
    time.sleep(0.1)
sys.exit(2)
"""


def missing_rviz() -> str | None:
    """Why Debian's rviz cannot be the oracle here, or None."""
    for path in (RVIZ, XVFB_RUN):
        if not path.exists():
            return (
                f"{path} is not installed (scripts/install.sh --dev installs rviz, xvfb and xauth)"
            )
    return missing_debian_ros("rospy, rosgraph, genpy")


@dataclass
class RvizRun:
    output: str
    """What rviz printed (stdout and stderr)."""
    came_up: bool
    """rviz loaded the config and offered its services (and saved, when asked)."""

    def complaints(self) -> list[str]:
        """rviz's lines about something it could not do (errors, warnings, failures)."""
        bad = re.compile(r"\[ ?ERROR\]|\[ ?WARN\]|Failed|Invalid")
        return [line for line in self.output.splitlines() if bad.search(line)]


def open_in_rviz(config: Path, core: Roscore, workdir: Path, *, save_to: Path | None) -> RvizRun:
    """Open ``config`` in rviz, save it to ``save_to`` through rviz when given, and stop it."""
    node = f"rviz_{secrets.token_hex(4)}"
    home = workdir / "home"
    home.mkdir(parents=True, exist_ok=True)
    env = ros_env(core.port, core.home)
    env.update(HOME=str(home), XDG_RUNTIME_DIR=str(home))
    log = workdir / f"{node}.log"
    with log.open("wb") as out:
        rviz = subprocess.Popen(
            [str(XVFB_RUN), "-a", str(RVIZ), "-d", str(config), f"__name:={node}"],
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            start_new_session=True,
        )
    try:
        probe = subprocess.run(
            [str(ROS_PYTHON), "-c", _SAVE, f"/{node}", str(save_to or ""), str(WAIT_S)],
            env=env,
            capture_output=True,
            check=False,
            timeout=WAIT_S + 10,
        )
    finally:
        _stop(rviz)
    output = log.read_text(encoding="utf-8", errors="replace")
    if probe.returncode not in (0, 2, 3):
        output += "\n[probe] " + probe.stderr.decode(errors="replace")
    return RvizRun(output, probe.returncode == 0)


def _stop(process: subprocess.Popen[bytes]) -> None:
    """Stop xvfb-run, rviz and Xvfb (one process group)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(process.pid, signal.SIGTERM)
    try:
        process.wait(timeout=10)
    except subprocess.TimeoutExpired:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGKILL)
        process.wait(timeout=10)
