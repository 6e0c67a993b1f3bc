"""The runtime layer called as a batch runner or a ROS master would call it: plain values,
no command line."""

from __future__ import annotations

import logging
import subprocess
import sys

import pytest

from belvedere.errors import BelvedereError
from belvedere.graph import Graph
from belvedere.launch import LaunchConfig
from belvedere.packages import PackageIndex
from belvedere.runtime import GraphAddress, ScriptOptions, SessionOptions, run_session
from belvedere.runtime._clock import hold_time_base


def test_a_session_runs_from_plain_values(
    endpoint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    options = SessionOptions(
        address=GraphAddress(endpoint=endpoint),
        duration=0.5,
        rtf=None,
        headless=True,
        pubs=("/chatter std_msgs/String {data: hi}",),
        echoes=("/chatter",),
    )
    assert run_session(LaunchConfig(), PackageIndex.from_environment(), options) == 0
    out = capsys.readouterr().out
    assert out == 'data: "hi"\n---\n'


def test_scripted_runs_are_checked_before_anything_starts() -> None:
    with pytest.raises(BelvedereError, match=r"--pub expects 'TOPIC TYPE YAML'"):
        ScriptOptions.parse(["/chatter"], [])
    with pytest.raises(BelvedereError, match=r"--duration expects a positive number"):
        ScriptOptions.parse([], [], duration=0)
    parsed = ScriptOptions.parse(["chatter std_msgs/String {data: hi}"], ["odom"])
    assert [(topic, kind) for topic, kind, _ in parsed.pubs] == [
        ("/chatter", "std_msgs/msg/String")
    ]
    assert parsed.echoes == ("/odom",)


def test_the_graph_keeps_the_time_of_the_process_that_made_it(
    caplog: pytest.LogCaptureFixture,
) -> None:
    config = LaunchConfig()
    config.set_param("/use_sim_time", False, None)
    graph = Graph(sim_time=True)
    try:
        with caplog.at_level(logging.WARNING, logger="belvedere"):
            hold_time_base(config, graph)
    finally:
        graph.shutdown()
    assert "/use_sim_time" not in config.params
    assert "this launch simulates time" in caplog.text


def test_importing_the_runtime_loads_neither_the_command_line_nor_what_a_session_starts() -> None:
    code = (
        "import sys, belvedere.runtime\n"
        "heavy = ('belvedere.cli', 'belvedere.launch', 'belvedere.nodes', 'belvedere.foxglove',"
        " 'belvedere.viewer', 'belvedere.sim', 'argparse')\n"
        "print(sorted(m for m in sys.modules if m.startswith(heavy)))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True
    )
    assert done.stdout == "[]\n"
