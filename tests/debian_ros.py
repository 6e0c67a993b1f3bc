"""Where Debian's ROS 1 lives, and whether it is here (the oracles of the differential tests)."""

from __future__ import annotations

import subprocess
from pathlib import Path

__all__ = ["ROSCORE", "ROS_PYTHON", "missing_debian_ros"]

ROSCORE = Path("/usr/bin/roscore")
ROS_PYTHON = Path("/usr/bin/python3")


def missing_debian_ros(modules: str, *paths: Path) -> str | None:
    """Why Debian's ROS cannot run here (roscore, ``paths``, or ``import modules`` under its
    Python), or None."""
    for path in (ROSCORE, ROS_PYTHON, *paths):
        if not path.exists():
            return f"{path} is not installed (scripts/install.sh --dev installs Debian's ROS 1)"
    probe = subprocess.run(
        [str(ROS_PYTHON), "-c", f"import {modules}"], capture_output=True, check=False
    )
    if probe.returncode != 0:
        return "rospy or the message packages are not installed for /usr/bin/python3"
    return None
