"""One graph per session: domains keep graphs apart, tools say which they joined, and a node
name taken again replaces the older node, as ROS 1's master does — with real processes."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from belvedere.cli import main
from belvedere.graph import (
    DEFAULT_ENDPOINT,
    MAX_DOMAIN,
    TransportError,
    check_domain,
    domain_endpoint,
)
from tests.conftest import TEST_DOMAIN

BELVEDERE = [sys.executable, "-m", "belvedere"]
HOST = socket.gethostname()

NODE_SCRIPT = """
import logging, sys, time
from belvedere.graph import Graph, ZenohTransport
logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s")
g = Graph(sim_time=False, transport=ZenohTransport())
g.params.set("/who", sys.argv[2])
n = g.create_node("arbotix")
odom = n.publisher("/odom", "nav_msgs/Odometry")
n.timer(0.05, lambda: odom.publish_data({}))
g.start(rtf=None)
print("READY", flush=True)
deadline = time.monotonic() + 30  # a bound, not a measurement: the test waits for "closed"
# the shutdown runs on the executor: closed at its start, out of the graph at its end
while (
    sys.argv[1] == "until-replaced"
    and (not n.closed or "/arbotix" in g.nodes)
    and time.monotonic() < deadline
):
    time.sleep(0.05)
print("closed" if n.closed else "open", "/arbotix" in g.nodes, odom.count, flush=True)
sys.stdin.read()
print(odom.count, flush=True)
g.shutdown()
"""


def test_domain_numbers_and_their_endpoints(monkeypatch: pytest.MonkeyPatch) -> None:
    assert domain_endpoint(0) == DEFAULT_ENDPOINT == "tcp/127.0.0.1:7450"
    assert domain_endpoint(7) == "tcp/127.0.0.1:7457"
    assert domain_endpoint(MAX_DOMAIN) == "tcp/127.0.0.1:7682"
    assert check_domain(5) == 5
    assert check_domain("12") == 12
    monkeypatch.setenv("BELVEDERE_DOMAIN", "9")
    assert check_domain() == 9
    monkeypatch.delenv("BELVEDERE_DOMAIN")
    assert check_domain() == 0
    for bad in ("-1", "233", "seven", "1.5"):
        monkeypatch.setenv("BELVEDERE_DOMAIN", bad)
        with pytest.raises(
            TransportError,
            match=rf"^error: BELVEDERE_DOMAIN '{bad}' is not a graph domain "
            r"\(a whole number from 0 to 232\)$",
        ):
            check_domain()


def test_a_bad_domain_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["topic", "list", "--domain", "300"]) == 2
    assert "argument --domain: domain '300' is not a graph domain" in capsys.readouterr().err
    assert main(["sim", "robot.urdf", "--domain", "x"]) == 2
    assert "argument --domain: domain 'x' is not a graph domain" in capsys.readouterr().err


def run(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*BELVEDERE, *args], capture_output=True, text=True, timeout=30, check=False, env=env
    )


def test_tools_say_which_graph_they_joined(own_graph: str) -> None:
    listed = run("topic", "list")
    assert listed.returncode == 0, listed.stderr
    assert listed.stdout == ""  # data only
    assert listed.stderr == f"graph: domain {TEST_DOMAIN} ({own_graph}, listening)\n"
    assert run("-q", "topic", "list").stderr == ""
    assert (
        run("node", "list", "--domain", "17").stderr
        == f"graph: domain 17 ({own_graph}, listening)\n"
    )


class Peer:
    """A process with the node /arbotix publishing /odom at 20 Hz, as a sim would."""

    def __init__(self, tmp_path: Path, mode: str, name: str, env: dict[str, str]) -> None:
        script = tmp_path / "arbotix.py"
        script.write_text(NODE_SCRIPT)
        self.proc = subprocess.Popen(
            [sys.executable, str(script), mode, name],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )
        assert self.readline() == "READY"

    @property
    def pid(self) -> int:
        return self.proc.pid

    def readline(self) -> str:
        assert self.proc.stdout is not None
        return self.proc.stdout.readline().strip()

    def finish(self) -> tuple[str, str]:
        out, err = self.proc.communicate(timeout=20)
        return out, err


@pytest.fixture
def peers(tmp_path: Path) -> Iterator[Any]:
    started: list[Peer] = []

    def start(mode: str, name: str, **env: str) -> Peer:
        peer = Peer(tmp_path, mode, name, {**os.environ, **env})
        started.append(peer)
        return peer

    yield start
    for peer in started:
        if peer.proc.poll() is None:
            peer.proc.kill()
            peer.proc.wait(timeout=10)


def test_domains_on_one_endpoint_stay_apart(peers: Any) -> None:
    first = peers("stay", "first", BELVEDERE_DOMAIN="3")
    second = peers("stay", "second", BELVEDERE_DOMAIN="4")
    # Same node name, other domain: nobody is replaced.
    assert first.readline().startswith("open True")
    assert second.readline().startswith("open True")
    for domain, who in (("3", "first"), ("4", "second")):
        assert run("param", "get", "/who", "--domain", domain).stdout == f"{who}\n"
        assert run("node", "list", "--domain", domain).stdout == "/arbotix\n"
    assert run("node", "list", "--domain", "5").stdout == ""
    for peer in (first, second):
        _, err = peer.finish()
        assert err == ""


def _free_domain(taken: set[int]) -> int:
    for domain in range(200, MAX_DOMAIN):
        if domain in taken or domain == TEST_DOMAIN:
            continue
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", 7450 + domain))
            except OSError:
                continue
        return domain
    pytest.skip("no domain with a free port")


def test_the_domain_picks_the_endpoint(peers: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("BELVEDERE_ENDPOINT")
    mine = _free_domain(set())
    other = _free_domain({mine})
    peer = peers("stay", "peer", BELVEDERE_DOMAIN=str(mine))
    joined = run("node", "list", "--domain", str(mine))
    assert joined.stdout == "/arbotix\n"
    assert joined.stderr == f"graph: domain {mine} (tcp/127.0.0.1:{7450 + mine}, connected)\n"
    apart = run("node", "list", "--domain", str(other))
    assert apart.stdout == ""
    assert apart.stderr == f"graph: domain {other} (tcp/127.0.0.1:{7450 + other}, listening)\n"
    assert peer.readline().startswith("open True")


def test_a_node_name_taken_again_replaces_the_older_node(peers: Any) -> None:
    older = peers("until-replaced", "older")
    newer = peers("stay", "newer")
    assert newer.readline().startswith("open True")
    closed, in_graph, published = older.readline().split()
    assert (closed, in_graph) == ("closed", "False")
    assert run("node", "list").stdout == "/arbotix\n"
    info = run("node", "info", "/arbotix").stdout
    assert f"Process: pid {newer.pid} on {HOST}\n" in info
    assert f"pid {older.pid}" not in info
    assert run("param", "get", "/who").returncode == 0  # both graphs still serve parameters
    out, err = older.finish()
    assert out.strip() == published  # the older node published nothing more
    assert err == (
        f"WARNING: node /arbotix (pid {older.pid} on {HOST}) was replaced by a new node of "
        f"that name in pid {newer.pid} on {HOST}: shutting it down here, as in ROS 1\n"
    )
    _, err = newer.finish()
    assert err == (
        f"WARNING: node /arbotix (pid {newer.pid} on {HOST}) replaces the node of that name "
        f"in pid {older.pid} on {HOST}, which is shut down, as in ROS 1\n"
    )
