"""A node's log: ROS's lines on the terminal (directly when nothing listens to Python's
logging, through it when something does) and rosgraph_msgs/Log on /rosout."""

from __future__ import annotations

import logging
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from belvedere.graph import Graph
from belvedere.graph._log import ros_level
from tests.conftest import REPO

SCRIPT = """
import logging
from belvedere.graph import Graph

graph = Graph()  # simulated time
node = graph.create_node("talker", namespace="/robot")
graph.run(duration=1.5)
node.logger.info("hello %d", 1)
node.logger.debug("not shown at the default level")
node.logger.warning("careful")
try:
    1 / 0
except ZeroDivisionError:
    node.logger.exception("failed")
node.logger.setLevel(logging.DEBUG)
node.logger.debug("shown now")
"""


def _masked(text: str) -> str:
    """Log lines with the wall clock's time replaced (the simulated one stays)."""
    return re.sub(r"^\[(\w+)\] \[\d+\.\d{6}", r"[\1] [WALL", text, flags=re.M)


def test_a_script_that_configures_nothing_prints_rospys_lines(tmp_path: Path) -> None:
    script = tmp_path / "logs.py"
    script.write_text(SCRIPT)
    done = subprocess.run(
        [sys.executable, str(script)],
        capture_output=True,
        text=True,
        check=True,
        env={"PYTHONPATH": str(REPO / "src"), "PATH": "/usr/bin:/bin"},
    )
    assert _masked(done.stdout) == (
        "[INFO] [WALL, 1.500000]: hello 1\n[DEBUG] [WALL, 1.500000]: shown now\n"
    )
    err = _masked(done.stderr).splitlines()
    assert err[:3] == [
        "[WARN] [WALL, 1.500000]: careful",
        "[ERROR] [WALL, 1.500000]: failed",
        "Traceback (most recent call last):",
    ]
    assert err[-1] == "ZeroDivisionError: division by zero"


def test_each_message_goes_to_rosout(caplog: pytest.LogCaptureFixture) -> None:
    graph = Graph()
    node = graph.create_node("talker", namespace="/robot")
    node.publisher("chatter", "std_msgs/String")
    logs: list[Any] = []
    graph.create_node("watcher").subscribe("/rosout", "rosgraph_msgs/Log", logs.append)
    graph.run(duration=0.25)
    with caplog.at_level(logging.DEBUG, logger="belvedere.node"):
        node.logger.info("hello %s", "there")
        line = sys._getframe().f_lineno - 1
        node.logger.error("bad")
    graph.spin_once()
    assert [(m.level, m.name, m.msg) for m in logs] == [
        (2, "/robot/talker", "hello there"),
        (8, "/robot/talker", "bad"),
    ]
    first = logs[0]
    assert (first.header.stamp.sec, first.header.stamp.nanosec) == (0, 250_000_000)
    assert (first.file, first.line, first.function) == (
        __file__,
        line,
        "test_each_message_goes_to_rosout",
    )
    assert first.topics == ["/robot/chatter", "/rosout"]
    # something listens to Python's logging (pytest): the records go there, with ROS's line
    records = [r for r in caplog.records if r.name == "belvedere.node.talker"]
    assert [r.getMessage() for r in records] == ["hello there", "bad"]
    assert getattr(records[0], "ros_line", "").endswith(", 0.250000]: hello there")
    assert records[0].lineno == line


def test_python_levels_map_to_ros_levels() -> None:
    assert [ros_level(n) for n in (5, 10, 20, 25, 30, 40, 50, 60)] == [1, 1, 2, 2, 4, 8, 16, 16]
