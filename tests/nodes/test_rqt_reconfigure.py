"""``belvedere run rqt_reconfigure rqt_reconfigure``'s command line: ROS's usage for
``--help``, one error naming an option it does not take, a bad ``~port`` named."""

from __future__ import annotations

import subprocess
import sys

from tests.waiting import DEADLINE

RUN = [sys.executable, "-m", "belvedere", "run", "rqt_reconfigure", "rqt_reconfigure"]


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*RUN, *args], capture_output=True, text=True, timeout=DEADLINE, check=False
    )


def test_help_prints_the_usage(endpoint: str) -> None:
    ran = _run("--help")
    assert ran.returncode == 0, ran.stderr
    assert ran.stdout.startswith("usage: rqt_reconfigure [-h] [NODE ...]")


def test_an_unknown_option_and_a_bad_port_are_one_error_each(endpoint: str) -> None:
    ran = _run("--force-discover")
    assert ran.returncode == 1
    assert "rqt_reconfigure takes no option --force-discover" in ran.stderr
    assert "Traceback" not in ran.stderr
    ran = _run("_port:=-4")
    assert ran.returncode == 1
    assert "parameter ~port: expected a port number (0 to 65535), got -4" in ran.stderr
