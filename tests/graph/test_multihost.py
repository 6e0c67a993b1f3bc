"""One graph across hosts, on one machine: each "host" on its own loopback address (Linux
routes all of 127.0.0.0/8 to lo), real processes, the graph guarded by its token. The tests
never contact the machine's other addresses."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from belvedere.graph import HostAccess, HostAccessError, check_token, new_token
from belvedere.graph._hosts import is_loopback_endpoint
from tests.processes import BelvedereProcess
from tests.waiting import DEADLINE

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "examples/mbot_description/urdf/xacro/gazebo/mbot_gazebo.xacro"
HOST_A = "127.0.0.2"


def _free_port(host: str) -> int:
    with socket.socket() as sock:
        sock.bind((host, 0))
        port: int = sock.getsockname()[1]
    return port


def _host_env(**graph: str) -> dict[str, str]:
    """The environment of a process on "another host": none of the test's own graph."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("BELVEDERE_")}
    env.update(graph)
    return env


def _belvedere(args: list[str], env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "belvedere", *args],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
        env=env,
    )


@pytest.fixture(params=["tcp", "tls"])
def host_a(request: pytest.FixtureRequest) -> Iterator[tuple[str, str]]:
    """A simulation on "host" 127.0.0.2 opened with ``--listen`` (plain TCP, or TLS with the
    token's certificates): (endpoint, its token)."""
    endpoint = f"{request.param}/{HOST_A}:{_free_port(HOST_A)}"
    saved, host_env = dict(os.environ), _host_env()
    os.environ.clear()
    os.environ.update(host_env)
    try:
        sim = BelvedereProcess(
            ["sim", str(MODEL), "--headless", "--listen", endpoint],
            ready="ArbotiX being simulated",
            ended="the listening simulation ended",
        )
    finally:
        os.environ.clear()
        os.environ.update(saved)
    printed = "".join(sim.lines)
    assert f"export BELVEDERE_CONNECT={endpoint} BELVEDERE_TOKEN=" in printed
    token = printed.split("BELVEDERE_TOKEN=", 1)[1].split()[0]
    assert f"graph: domain 0 ({endpoint}, listening)" in printed
    yield endpoint, token
    sim.stop()


def test_a_host_with_the_token_joins_the_graph(host_a: tuple[str, str]) -> None:
    endpoint, token = host_a
    env = _host_env(BELVEDERE_TOKEN=token)
    echo = _belvedere(["topic", "echo", "-n", "1", "/odom", "--connect", endpoint], env)
    assert echo.returncode == 0, echo.stderr
    assert 'frame_id: "odom"' in echo.stdout
    assert f"({endpoint}, connected)" in echo.stderr
    # the environment alone, as a second machine's shell would set it
    env = _host_env(BELVEDERE_CONNECT=endpoint, BELVEDERE_TOKEN=token)
    nodes = _belvedere(["node", "list"], env)
    assert nodes.returncode == 0, nodes.stderr
    assert "/robot_state_publisher" in nodes.stdout.split()


def test_a_peer_without_the_token_is_refused(host_a: tuple[str, str]) -> None:
    endpoint, token = host_a
    missing = _belvedere(["topic", "list", "--connect", endpoint], _host_env())
    assert missing.returncode == 1
    assert "error: joining the graph at" in missing.stderr
    assert "needs its token" in missing.stderr
    assert "Traceback" not in missing.stderr
    # asked to stay on loopback, TCP tries without one: the host's authentication refuses it
    unguarded = _belvedere(["topic", "list", "--endpoint", endpoint], _host_env())
    assert unguarded.returncode == 1
    expected = (
        f"a graph open to other hosts ({endpoint}) needs a token"  # TLS: no certificates
        if endpoint.startswith("tls/")
        else f"the graph at {endpoint} refused this process: its token is missing"
    )
    assert expected in unguarded.stderr
    wrong = new_token()
    assert wrong != token
    refused = _belvedere(["topic", "list", "--connect", endpoint, "--token", wrong], _host_env())
    assert refused.returncode == 1
    assert f"the graph at {endpoint} refused this process: its token is wrong" in refused.stderr


def test_a_graph_off_loopback_never_opens_without_a_token() -> None:
    # refused before any socket is opened: nothing listens on the machine's addresses
    port = _free_port("127.0.0.1")
    ran = _belvedere(["topic", "list", "--endpoint", f"tcp/0.0.0.0:{port}"], _host_env())
    assert ran.returncode == 1
    assert f"a graph open to other hosts (tcp/0.0.0.0:{port}) needs a token" in ran.stderr
    bad = _belvedere(["topic", "list", "--connect", "somewhere"], _host_env())
    assert bad.returncode == 2
    assert "'somewhere' is not a graph endpoint (tcp/HOST:PORT)" in bad.stderr


def test_host_access_rules(monkeypatch: pytest.MonkeyPatch) -> None:
    for var in ("BELVEDERE_LISTEN", "BELVEDERE_CONNECT", "BELVEDERE_TOKEN", "BELVEDERE_DISCOVER"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.delenv("BELVEDERE_ENDPOINT", raising=False)
    plain = HostAccess.from_environment()
    assert plain.endpoint(None, "tcp/127.0.0.1:7450") == "tcp/127.0.0.1:7450"
    assert plain.guard("tcp/127.0.0.1:7450") is None
    assert plain.guard("tcp/[::1]:7450") is None
    with pytest.raises(HostAccessError, match="needs a token"):
        plain.guard("tcp/192.0.2.1:7450")  # documentation address: only checked, not used
    assert is_loopback_endpoint("tcp/localhost:1")
    assert not is_loopback_endpoint("tcp/robot.local:1")
    token = new_token()
    assert check_token(token) == token
    with pytest.raises(HostAccessError, match="not a graph token"):
        check_token("short")
    with pytest.raises(HostAccessError, match="not a graph token"):
        check_token("a" * 20 + ":evil\nuser")  # would add a line to Zenoh's dictionary
    monkeypatch.setenv("BELVEDERE_LISTEN", "tcp/127.0.0.3:7450")
    monkeypatch.setenv("BELVEDERE_CONNECT", "tcp/127.0.0.4:7450")
    both = HostAccess.from_environment()
    assert both.endpoint("tcp/127.0.0.1:1", "d") == "tcp/127.0.0.1:1"  # --endpoint first
    assert both.endpoint(None, "d") == "tcp/127.0.0.4:7450"  # then where it connects
    with pytest.raises(HostAccessError, match="needs its token"):
        both.guard("tcp/127.0.0.4:7450")
    monkeypatch.delenv("BELVEDERE_CONNECT")
    with pytest.raises(HostAccessError, match="needs a token"):
        HostAccess.from_environment().guard("tcp/127.0.0.3:7450")  # --listen, even on lo
    monkeypatch.setenv("BELVEDERE_TOKEN", token)
    assert HostAccess.from_environment().guard("tcp/127.0.0.3:7450") == token
    monkeypatch.delenv("BELVEDERE_LISTEN")
    monkeypatch.delenv("BELVEDERE_TOKEN")
    monkeypatch.setenv("BELVEDERE_DISCOVER", "1")
    with pytest.raises(HostAccessError, match="needs a token"):
        HostAccess.from_environment().guard("tcp/127.0.0.1:7450")  # scouting the LAN


def test_navigation_on_one_host_localises_the_robot_simulated_on_another() -> None:
    """The course's split: Gazebo's world on the robot's host, map_server, amcl, move_base
    and rviz (headless) on the laptop; amcl's pose needs the other host's /scan, /odom and
    /clock, so it proves the graph is one."""
    endpoint = f"tcp/{HOST_A}:{_free_port(HOST_A)}"
    examples = str(ROOT / "examples")

    def launch(path: str) -> list[str]:
        return ["launch", "--headless", "--package-path", path]

    saved, host_env = dict(os.environ), _host_env()
    os.environ.clear()
    os.environ.update(host_env)
    try:
        sim = BelvedereProcess(
            [
                *launch(examples),
                "mbot_gazebo",
                "mbot_laser_nav_gazebo.launch",
                "--listen",
                endpoint,
            ],
            ready="graph: domain 0",
            ended="the simulation host's launch ended",
        )
        token = "".join(sim.lines).split("BELVEDERE_TOKEN=", 1)[1].split()[0]
        os.environ.update(BELVEDERE_CONNECT=endpoint, BELVEDERE_TOKEN=token)
        nav = BelvedereProcess(
            [*launch(examples), "mbot_navigation", "nav_cloister_demo.launch"],
            ready="graph: domain 0",
            ended="the navigation host's launch ended",
        )
    finally:
        os.environ.clear()
        os.environ.update(saved)
    try:
        assert f"({endpoint}, connected)" in nav.ready
        env = _host_env(BELVEDERE_CONNECT=endpoint, BELVEDERE_TOKEN=token)
        pose = _belvedere(["topic", "echo", "-n", "1", "/amcl_pose"], env)
        assert pose.returncode == 0, pose.stderr
        assert 'frame_id: "map"' in pose.stdout
        # stamped in the simulation's time, whose /clock only the other host publishes
        stamp = pose.stdout.split("secs:", 1)[1].split("nsecs:", 1)
        assert int(stamp[0]) + int(stamp[1].split()[0]) > 0, pose.stdout
        nodes = _belvedere(["node", "list"], env).stdout.split()
        assert {"/gazebo", "/amcl", "/move_base", "/map_server"} <= set(nodes)
    finally:
        nav.stop()
        sim.stop()


DISCOVER_SCRIPT = """
set -e
ip link set lo up multicast on
ip route add 224.0.0.0/4 dev lo
"$PYTHON" -m belvedere sim "$MODEL" --headless --discover --endpoint tcp/127.0.0.2:7450 \
    2>"$LOG" &
trap 'kill -INT $!; wait $!' EXIT
"$PYTHON" -m belvedere topic echo -n 1 /odom --discover --endpoint tcp/127.0.0.3:7450
"""


def test_discover_finds_the_graph_by_scouting_inside_a_network_namespace(
    tmp_path: Path,
) -> None:
    """``--discover``: no endpoint names the other host, Zenoh's multicast scouting finds it —
    only inside a network namespace the test makes, where lo is the only interface."""
    unshare, ip = shutil.which("unshare"), shutil.which("ip")
    if unshare is None or ip is None:
        pytest.skip("unshare or ip (iproute2) is not installed")
    if subprocess.run([unshare, "-n", "true"], check=False, capture_output=True).returncode:
        pytest.skip("cannot make a network namespace here (needs root or user namespaces)")
    env = _host_env(
        BELVEDERE_TOKEN=new_token(),
        PYTHON=sys.executable,
        MODEL=str(MODEL),
        LOG=str(tmp_path / "sim.log"),
    )
    ran = subprocess.run(
        [unshare, "-n", "bash", "-c", DISCOVER_SCRIPT],
        capture_output=True,
        text=True,
        timeout=DEADLINE,
        check=False,
        env=env,
    )
    log = (tmp_path / "sim.log").read_text()
    assert ran.returncode == 0, ran.stderr + log
    assert 'frame_id: "odom"' in ran.stdout
    assert "(tcp/127.0.0.2:7450, listening)" in log
    assert "(tcp/127.0.0.3:7450, listening)" in ran.stderr  # each its own peer, found by scouting


def test_tls_certificates_are_the_tokens_alone(tmp_path: Path) -> None:
    """Two hosts with one token build the same certificates (nothing to copy); another token
    makes others, which the first graph's authority does not sign."""
    from cryptography import x509
    from cryptography.exceptions import InvalidSignature

    token = new_token()
    script = (
        "import sys; from belvedere.graph._tls import tls_settings\n"
        "s = tls_settings(sys.argv[1])\n"
        "sys.stdout.write(''.join(open(s[k]).read() for k in "
        "('root_ca_certificate', 'listen_certificate', 'listen_private_key')))"
    )
    made = [
        subprocess.run(
            [sys.executable, "-c", script, t], capture_output=True, text=True, check=True
        ).stdout
        for t in (token, token, new_token())
    ]
    assert made[0] == made[1]
    assert "BEGIN PRIVATE KEY" in made[0]
    ours, theirs = (x509.load_pem_x509_certificates(m.encode()) for m in (made[0], made[2]))
    assert made[0] != made[2]
    ours[1].verify_directly_issued_by(ours[0])
    with pytest.raises(InvalidSignature):
        theirs[1].verify_directly_issued_by(ours[0])


def test_a_new_token_is_never_read_as_an_option() -> None:
    """``--token TOKEN`` takes any token ``new_token`` makes: none starts with ``-``."""
    assert not any(new_token().startswith("-") for _ in range(2000))
