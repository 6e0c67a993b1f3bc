"""Debian's ROS 1, the reference the start-up and first-message benchmarks measure against
(not a benchmark itself)."""

from __future__ import annotations

import socket
from typing import Final

DEBIAN_PYTHON: Final = "/usr/bin/python3"
"""Debian's Python, which imports Debian's rospy."""
ROSCORE: Final = "/usr/bin/roscore"


def free_port() -> int:
    """A TCP port free on loopback now."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port
